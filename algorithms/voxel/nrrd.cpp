// NRRD0004, raw encoding: one sample per voxel, at its centre.
#include <string>
#include <vector>

#include "voxel/voxel_file_parts.h"
#include "voxel/voxel_io.h"

namespace cgview {

using namespace voxel_file;

namespace {

// Splits "key: value" header lines up to an empty line (NRRD).
std::vector<std::pair<std::string, std::string>> header_fields(const std::string& bytes, std::size_t& end) {
  std::vector<std::pair<std::string, std::string>> out;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t nl = bytes.find('\n', pos);
    if (nl == std::string::npos) {
      end = std::string::npos;
      return out;
    }
    std::string line = bytes.substr(pos, nl - pos);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    pos = nl + 1;
    if (line.empty()) break;
    if (line[0] == '#') continue;
    std::size_t c = line.find(":=");
    std::size_t skip = 2;
    if (c == std::string::npos) {
      c = line.find(": ");
      skip = 2;
    }
    if (c == std::string::npos) {
      out.push_back({line, ""});
      continue;
    }
    out.push_back({line.substr(0, c), line.substr(c + skip)});
  }
  end = pos;
  return out;
}

}  // namespace

std::string encode_nrrd(const VoxelGrid& g) {
  const auto d = g.dims();
  const double s = g.voxel_size();
  const Vec3 c = g.origin() + Vec3{0.5, 0.5, 0.5} * s;
  const bool f = g.type() == VoxelType::float32;
  std::string out = "NRRD0004\n# cgview voxel grid: one sample per voxel, at its centre\n";
  out += std::string("type: ") + (f ? "float" : "uint8") + "\ndimension: 3\nspace: 3D-right-handed\n";
  out += "sizes: " + std::to_string(d[0]) + " " + std::to_string(d[1]) + " " + std::to_string(d[2]) + "\n";
  out += "space directions: (" + num(s) + ",0,0) (0," + num(s) + ",0) (0,0," + num(s) + ")\n";
  out += "kinds: domain domain domain\nendian: little\nencoding: raw\n";
  out += "space origin: (" + num(c.x) + "," + num(c.y) + "," + num(c.z) + ")\n";
  out += std::string("cgview_type:=") + (g.type() == VoxelType::bit ? "bit" : f ? "float32" : "uint8") + "\n\n";
  out += payload(g);
  return out;
}

VoxelGrid decode_nrrd(const std::string& bytes, const std::string& name) {
  if (bytes.compare(0, 4, "NRRD") != 0) bad(name, "not a NRRD file (no 'NRRD' magic)", 0);
  std::size_t end = 0;
  const auto fields = header_fields(bytes, end);
  if (end == std::string::npos) bad(name, "the header does not end with an empty line");
  std::string type, encoding = "raw", endian = "little", cg;
  std::vector<double> sizes, dirs, origin;
  for (const auto& [k, v] : fields) {
    if (k == "type") type = v;
    else if (k == "encoding") encoding = v;
    else if (k == "endian") endian = v;
    else if (k == "sizes") sizes = numbers_in(v);
    else if (k == "space directions") dirs = numbers_in(v);
    else if (k == "space origin") origin = numbers_in(v);
    else if (k == "cgview_type") cg = v;
    else if (k == "dimension" && v != "3") bad(name, "only 3D images are voxel grids (dimension: " + v + ")");
  }
  VoxelType t;
  if (type == "float") t = VoxelType::float32;
  else if (type == "uint8" || type == "uchar" || type == "unsigned char" || type == "uint8_t") t = VoxelType::uint8;
  else bad(name, "type '" + type + "' is not read (uint8 or float)");
  if (cg == "bit") t = VoxelType::bit;
  if (encoding != "raw") bad(name, "encoding '" + encoding + "' is not read (raw)");
  if (t == VoxelType::float32 && endian != "little") bad(name, "big-endian data is not read");
  if (sizes.size() != 3) bad(name, "'sizes' needs 3 numbers");
  double s = 1;
  if (dirs.size() == 9) s = dirs[0];
  Vec3 c = origin.size() == 3 ? Vec3{origin[0], origin[1], origin[2]} : Vec3{};
  const auto d = checked_text_dims(sizes[0], sizes[1], sizes[2], name);
  VoxelGrid g = make_grid(d, c - Vec3{0.5, 0.5, 0.5} * s, s, t, name, bytes.size() - end);
  fill(g, bytes.data() + end, bytes.size() - end, name, end);
  return g;
}

}  // namespace cgview
