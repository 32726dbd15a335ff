// binvox 1 (Patrick Min): run-length bytes, y fastest, then z, then x.
#include <algorithm>
#include <string>

#include "voxel/voxel_file_parts.h"
#include "voxel/voxel_io.h"

namespace cgview {

using namespace voxel_file;

namespace {

// One byte per voxel: 0/1 for a bit grid, the value for uint8.
std::uint8_t byte_at(const VoxelGrid& g, std::size_t n) {
  return g.type() == VoxelType::float32 ? std::uint8_t(g.floats()[n] != 0.f) : g.bytes()[n];
}

}  // namespace

std::string encode_binvox(const VoxelGrid& g) {
  const auto d = g.dims();
  const int n = std::max({d[0], d[1], d[2]});
  const Vec3 o = g.origin();
  std::string out = "#binvox 1\ndim " + std::to_string(n) + " " + std::to_string(n) + " " + std::to_string(n) +
                    "\ntranslate " + num(o.x) + " " + num(o.y) + " " + num(o.z) + "\nscale " + num(n * g.voxel_size()) +
                    "\ndata\n";
  std::uint8_t value = 0;
  int count = 0;
  auto push = [&](std::uint8_t v) {
    if (count > 0 && (v != value || count == 255)) {
      out += char(value);
      out += char(count);
      count = 0;
    }
    value = v;
    ++count;
  };
  for (int x = 0; x < n; ++x)
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y) {
        const bool inside = x < d[0] && y < d[1] && z < d[2];
        push(inside && byte_at(g, g.linear({x, y, z})) != 0 ? 1 : 0);
      }
  if (count > 0) {
    out += char(value);
    out += char(count);
  }
  return out;
}

VoxelGrid decode_binvox(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, 8, "#binvox ") != 0) bad(name, "not a binvox file (no '#binvox' line)", 0);
  std::size_t pos = 0;
  long long dims[3] = {0, 0, 0};
  Vec3 t{};
  double scale = 1;
  bool have_data = false;
  while (!have_data) {
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string::npos) bad(name, "the header has no 'data' line", pos);
    const std::size_t line_at = pos;
    std::string line = bytes.substr(pos, nl - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = nl + 1;
    std::istringstream in(line);
    in.imbue(std::locale::classic());
    std::string key;
    // Blank lines, comments (and "#binvox 1" itself) and unknown keywords
    // are skipped, as binvox's own viewer skips them.
    if (!(in >> key) || key.front() == '#') continue;
    if (key == "dim") in >> dims[0] >> dims[1] >> dims[2];
    else if (key == "translate") in >> t.x >> t.y >> t.z;
    else if (key == "scale") in >> scale;
    else if (key == "data") have_data = true;
    if (in.fail()) bad(name, "a malformed '" + key + "' line", line_at);
  }
  const auto d = checked_dims(dims[0], dims[1], dims[2], name);
  // Each run of two bytes holds at most 255 voxels: check the claim before allocating.
  const std::size_t runs_hold = 255 * ((bytes.size() - pos) / 2);
  if (double(d[0]) * d[1] * d[2] > double(runs_hold))
    bad(name, "the header claims more voxels than the runs can hold", pos);
  VoxelGrid g = make_grid(d, t, scale / std::max({d[0], d[1], d[2]}), VoxelType::bit, name, runs_hold);
  // y fastest, then z, then x.
  const std::size_t total = g.size();
  std::size_t n = 0;
  for (; pos + 1 < bytes.size() + 1 && n < total; pos += 2) {
    if (pos + 1 >= bytes.size()) bad(name, "a run is cut short", pos);
    const std::uint8_t v = std::uint8_t(bytes[pos]), c = std::uint8_t(bytes[pos + 1]);
    if (n + c > total) bad(name, "the runs hold more voxels than the grid", pos);
    for (int r = 0; r < c; ++r, ++n) {
      const int y = int(n % d[1]), z = int((n / d[1]) % d[2]), x = int(n / (std::size_t(d[1]) * d[2]));
      if (v) g.bytes()[g.linear({x, y, z})] = 1;
    }
  }
  if (n != total) bad(name, "the runs hold " + std::to_string(n) + " voxels, the grid " + std::to_string(total), pos);
  return g;
}

}  // namespace cgview
