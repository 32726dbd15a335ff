// Images that the renderer produces, PNG encoding and decoding (libpng),
// and a contact sheet of several images.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cgview::render {

// 8-bit RGBA, rows from the top; rgba.size() == 4 * width * height.
struct Image {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
};

// The PNG file's bytes (RGBA, 8 bits per channel).  Throws Error if libpng fails.
std::string encode_png(const Image& image);
// Any PNG libpng reads, converted to 8-bit RGBA.  Throws InvalidInput for bytes that are not a PNG.
Image decode_png(std::string_view bytes);

// The images laid out in a grid of `columns` (0: about square), each cell the
// size of the largest, on `background`.
Image contact_sheet(const std::vector<Image>& images, int columns = 0, std::uint32_t background_rgba = 0xFFFFFFFFu);

// A black-and-white picture of a binary mask (0 black, else white).
Image mask_image(const std::vector<std::uint8_t>& mask, int width, int height);

}  // namespace cgview::render
