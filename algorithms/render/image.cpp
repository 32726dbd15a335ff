#include "render/image.h"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/errors.h"

namespace cgview::render {

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgba.size() != std::size_t(4) * image.width * image.height)
    throw InvalidInput("encode_png: the image has no pixels or the wrong number of bytes");
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  img.width = png_uint_32(image.width);
  img.height = png_uint_32(image.height);
  img.format = PNG_FORMAT_RGBA;
  // The simplified API writes to memory in two calls: the size, then the bytes.
  png_alloc_size_t size = 0;
  if (!png_image_write_to_memory(&img, nullptr, &size, 0, image.rgba.data(), 0, nullptr))
    throw Error(std::string("encode_png: ") + img.message);
  std::string out(size, '\0');
  if (!png_image_write_to_memory(&img, out.data(), &size, 0, image.rgba.data(), 0, nullptr))
    throw Error(std::string("encode_png: ") + img.message);
  out.resize(size);
  return out;
}

Image decode_png(std::string_view bytes) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
    throw InvalidInput(std::string("decode_png: not a PNG: ") + img.message);
  img.format = PNG_FORMAT_RGBA;
  Image out;
  out.width = int(img.width);
  out.height = int(img.height);
  out.rgba.resize(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, out.rgba.data(), 0, nullptr)) {
    png_image_free(&img);
    throw InvalidInput(std::string("decode_png: ") + img.message);
  }
  return out;
}

Image contact_sheet(const std::vector<Image>& images, int columns, std::uint32_t bg) {
  if (images.empty()) throw InvalidInput("contact_sheet: no images");
  const int n = int(images.size());
  if (columns <= 0) columns = int(std::ceil(std::sqrt(double(n))));
  columns = std::min(columns, n);
  const int rows = (n + columns - 1) / columns;
  int cw = 0, ch = 0;
  for (const Image& im : images) {
    cw = std::max(cw, im.width);
    ch = std::max(ch, im.height);
  }
  Image out;
  out.width = cw * columns;
  out.height = ch * rows;
  out.rgba.resize(std::size_t(4) * out.width * out.height);
  const std::uint8_t b[4] = {std::uint8_t(bg >> 24), std::uint8_t(bg >> 16), std::uint8_t(bg >> 8), std::uint8_t(bg)};
  for (std::size_t i = 0; i < out.rgba.size(); ++i) out.rgba[i] = b[i % 4];
  for (int k = 0; k < n; ++k) {
    const Image& im = images[k];
    const int x0 = (k % columns) * cw + (cw - im.width) / 2, y0 = (k / columns) * ch + (ch - im.height) / 2;
    for (int y = 0; y < im.height; ++y)
      std::memcpy(&out.rgba[(std::size_t(y0 + y) * out.width + x0) * 4], &im.rgba[std::size_t(y) * im.width * 4],
                  std::size_t(im.width) * 4);
  }
  return out;
}

Image mask_image(const std::vector<std::uint8_t>& mask, int width, int height) {
  if (mask.size() != std::size_t(width) * height) throw InvalidInput("mask_image: the mask has the wrong size");
  Image out{width, height, std::vector<std::uint8_t>(mask.size() * 4, 255)};
  for (std::size_t i = 0; i < mask.size(); ++i) {
    const std::uint8_t v = mask[i] ? 255 : 0;
    out.rgba[4 * i] = out.rgba[4 * i + 1] = out.rgba[4 * i + 2] = v;
  }
  return out;
}

}  // namespace cgview::render
