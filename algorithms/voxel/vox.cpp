// MagicaVoxel .vox (version 150): SIZE and XYZI chunks and a palette.
#include <algorithm>
#include <cstring>
#include <string>

#include "voxel/voxel_file_parts.h"
#include "voxel/voxel_io.h"

namespace cgview {

using namespace voxel_file;

namespace {

void put32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
std::uint32_t get32(const std::string& s, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

}  // namespace

std::string encode_vox(const VoxelGrid& g) {
  const auto d = g.dims();
  if (d[0] > 256 || d[1] > 256 || d[2] > 256)
    throw InvalidInput("a MagicaVoxel .vox model holds at most 256 voxels per side; this grid is " +
                       std::to_string(d[0]) + "x" + std::to_string(d[1]) + "x" + std::to_string(d[2]) +
                       " (voxelize at a resolution of 254 or less with padding 1)");
  float lo = 0, hi = 1;
  if (g.type() == VoxelType::float32 && !g.floats().empty()) {
    const auto [a, b] = std::minmax_element(g.floats().begin(), g.floats().end());
    lo = *a, hi = *b > *a ? *b : *a + 1;
  }
  std::string xyzi;
  std::uint32_t count = 0;
  for (int z = 0; z < d[2]; ++z)
    for (int y = 0; y < d[1]; ++y)
      for (int x = 0; x < d[0]; ++x) {
        const std::size_t n = g.linear({x, y, z});
        int colour;
        if (g.type() == VoxelType::float32) {
          if (g.floats()[n] == 0.f) continue;
          colour = 1 + int(std::lround(254.0 * (g.floats()[n] - lo) / (hi - lo)));
        } else {
          if (!g.bytes()[n]) continue;
          colour = g.type() == VoxelType::bit ? 1 : g.bytes()[n];
        }
        xyzi += char(x), xyzi += char(y), xyzi += char(z), xyzi += char(std::clamp(colour, 1, 255));
        ++count;
      }
  std::string size_chunk = "SIZE";
  put32(size_chunk, 12), put32(size_chunk, 0), put32(size_chunk, d[0]), put32(size_chunk, d[1]),
      put32(size_chunk, d[2]);
  std::string xyzi_chunk = "XYZI";
  put32(xyzi_chunk, 4 + std::uint32_t(xyzi.size())), put32(xyzi_chunk, 0), put32(xyzi_chunk, count);
  xyzi_chunk += xyzi;
  std::string rgba = "RGBA";
  put32(rgba, 1024), put32(rgba, 0);
  for (int i = 0; i < 256; ++i) {  // entry i is colour index i + 1: a ramp from light grey
    const char v = char(std::clamp(230 - i * 180 / 255, 0, 255));
    rgba += v, rgba += v, rgba += v, rgba += char(255);
  }
  const std::string children = size_chunk + xyzi_chunk + rgba;
  std::string out = "VOX ";
  put32(out, 150);
  out += "MAIN";
  put32(out, 0), put32(out, std::uint32_t(children.size()));
  return out + children;
}

VoxelGrid decode_vox(const std::string& bytes, const std::string& name) {
  if (bytes.size() < 20 || bytes.compare(0, 4, "VOX ") != 0) bad(name, "not a MagicaVoxel file (no 'VOX ' magic)", 0);
  if (bytes.compare(8, 4, "MAIN") != 0) bad(name, "no MAIN chunk", 8);
  std::size_t at = 20;
  std::array<int, 3> d{0, 0, 0};
  std::size_t xyzi_at = 0, xyzi_n = 0;
  while (at + 12 <= bytes.size()) {
    const std::string id = bytes.substr(at, 4);
    const std::uint32_t content = get32(bytes, at + 4), children = get32(bytes, at + 8);
    if (at + 12 + std::uint64_t(content) > bytes.size()) bad(name, "chunk " + id + " is cut short", at);
    if (id == "SIZE" && d[0] == 0) {
      if (content < 12) bad(name, "a short SIZE chunk", at);
      d = checked_dims(get32(bytes, at + 12), get32(bytes, at + 16), get32(bytes, at + 20), name);
    } else if (id == "XYZI" && xyzi_at == 0) {
      if (content < 4) bad(name, "a short XYZI chunk", at);
      xyzi_n = get32(bytes, at + 12);
      if (4 + 4 * std::uint64_t(xyzi_n) > content) bad(name, "XYZI claims more voxels than it holds", at);
      xyzi_at = at + 16;
    }
    at += 12 + std::size_t(content) + children;
  }
  if (d[0] == 0 || xyzi_at == 0) bad(name, "no SIZE and XYZI chunks");
  VoxelGrid g = make_grid(d, {0, 0, 0}, 1.0, VoxelType::uint8, name, bytes.size());
  for (std::size_t v = 0; v < xyzi_n; ++v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data() + xyzi_at + 4 * v);
    const VoxelIndex idx{p[0], p[1], p[2]};
    if (!g.contains(idx)) bad(name, "a voxel outside SIZE", xyzi_at + 4 * v);
    g.bytes()[g.linear(idx)] = p[3];
  }
  return g;
}

}  // namespace cgview
