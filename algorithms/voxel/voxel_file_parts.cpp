#include "voxel/voxel_file_parts.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <locale>
#include <nlohmann/json.hpp>
#include <sstream>

namespace cgview::voxel_file {

std::string num(double v) {
  char buf[32];
  const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, p);
}

[[noreturn]] void bad(const std::string& name, const std::string& problem, std::optional<std::uint64_t> byte) {
  throw ParseError(name, problem, std::nullopt, byte);
}

std::string payload(const VoxelGrid& g) {
  if (g.type() == VoxelType::float32)
    return std::string(reinterpret_cast<const char*>(g.floats().data()), g.floats().size() * sizeof(float));
  return std::string(reinterpret_cast<const char*>(g.bytes().data()), g.bytes().size());
}

void fill(VoxelGrid& g, const char* data, std::size_t available, const std::string& name, std::uint64_t at) {
  const std::size_t need = g.size() * (g.type() == VoxelType::float32 ? sizeof(float) : 1);
  if (available < need)
    bad(name, "the data holds " + std::to_string(available) + " bytes, the grid needs " + std::to_string(need), at);
  if (g.type() == VoxelType::float32) std::memcpy(g.floats().data(), data, need);
  else {
    std::memcpy(g.bytes().data(), data, need);
    if (g.type() == VoxelType::bit)
      for (auto& b : g.bytes()) b = b != 0;
  }
}

std::array<int, 3> checked_dims(long long a, long long b, long long c, const std::string& name) {
  for (long long d : {a, b, c})
    if (d <= 0 || d > (1 << 20)) bad(name, "bad grid dimension " + std::to_string(d));
  return {int(a), int(b), int(c)};
}
// The same for sizes read as numbers from text: converting 1e100 (or NaN)
// to an integer is undefined (found by fuzz_voxel), so the range comes first.
std::array<int, 3> checked_text_dims(double a, double b, double c, const std::string& name) {
  for (double d : {a, b, c})
    if (!(d >= 1 && d <= (1 << 20)) || d != std::floor(d))
      bad(name,
          "bad grid dimension " + nlohmann::json(d).dump() + " (a whole number 1.." + std::to_string(1 << 20) + ")");
  return {int(a), int(b), int(c)};
}

VoxelGrid make_grid(std::array<int, 3> d, Vec3 origin, double size, VoxelType t, const std::string& name,
                    std::size_t available_bytes) {
  // A header's claim is checked against the bytes that follow before anything
  // is allocated: a byte a voxel (bit grids too: NRRD's, VTI's and raw's hold
  // one; fuzz_voxel found a 4 GB bit grid claimed by a 200-byte NRRD), four
  // for floats; binvox passes what its runs can hold.
  const double need = double(d[0]) * d[1] * d[2] * (t == VoxelType::float32 ? 4 : 1);
  if (need > double(available_bytes) + 0.5)
    bad(name, "the header claims " + std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]) +
                  " voxels, more than the file holds");
  if (!(size > 0) || !std::isfinite(size)) bad(name, "bad voxel size");
  return VoxelGrid(d, origin, size, t, std::uint64_t(1) << 36);
}

std::vector<double> numbers_in(const std::string& s) {
  std::vector<double> out;
  std::string t = s;
  for (char& c : t)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(t);
  in.imbue(std::locale::classic());
  double v;
  while (in >> v) out.push_back(v);
  return out;
}

}  // namespace cgview::voxel_file
