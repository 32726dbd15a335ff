// Internal: what the voxel file formats (binvox.cpp, nrrd.cpp, vti.cpp,
// vox.cpp, raw_voxels.cpp) share: numbers as text, the checks of a header's
// claims before anything is allocated, and a grid's values as bytes.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/voxel_grid.h"

namespace cgview::voxel_file {

static_assert(std::endian::native == std::endian::little, "the voxel writers assume a little-endian host");

// The most bytes a voxel file may have.
inline constexpr std::uint64_t kMaxRead = std::uint64_t(16) << 30;

// A number as the shortest text that reads back the same.
std::string num(double v);
// Throws ParseError naming the file (and the byte, when known).
[[noreturn]] void bad(const std::string& name, const std::string& problem,
                      std::optional<std::uint64_t> byte = std::nullopt);
// The values as stored in a file: uint8 per voxel, or float32.
std::string payload(const VoxelGrid& g);
// Fills a grid from uint8 or float32 bytes; checks the size first.
void fill(VoxelGrid& g, const char* data, std::size_t available, const std::string& name, std::uint64_t at);
// Dimensions read as integers, each 1..2^20 (else ParseError).
std::array<int, 3> checked_dims(long long a, long long b, long long c, const std::string& name);
// The same for sizes read as numbers from text: whole numbers in range.
std::array<int, 3> checked_text_dims(double a, double b, double c, const std::string& name);
// A grid of the claimed size, once the claim is checked against the bytes that follow.
VoxelGrid make_grid(std::array<int, 3> d, Vec3 origin, double size, VoxelType t, const std::string& name,
                    std::size_t available_bytes);
// The numbers in a text ("(1,2,3) (4,5,6)" -> 1..6).
std::vector<double> numbers_in(const std::string& s);

// .raw and its sidecar PATH.json (raw_voxels.cpp).
void write_raw_voxels(const VoxelGrid& grid, const std::filesystem::path& path);
VoxelGrid read_raw_voxels(const std::filesystem::path& path);

}  // namespace cgview::voxel_file
