#include "voxel/voxel_io.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"

namespace cgview {
namespace {

static_assert(std::endian::native == std::endian::little, "the voxel writers assume a little-endian host");

constexpr std::uint64_t kMaxRead = std::uint64_t(16) << 30;

std::string ext_of(const std::filesystem::path& p) { return ascii_lower(p.extension().string()); }

std::string num(double v) {
  char buf[32];
  const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, p);
}

[[noreturn]] void bad(const std::string& name, const std::string& problem,
                      std::optional<std::uint64_t> byte = std::nullopt) {
  throw ParseError(name, problem, std::nullopt, byte);
}

// One byte per voxel: 0/1 for a bit grid, the value for uint8.
std::uint8_t byte_at(const VoxelGrid& g, std::size_t n) {
  return g.type() == VoxelType::float32 ? std::uint8_t(g.floats()[n] != 0.f) : g.bytes()[n];
}

// The values as stored in a file: uint8 per voxel, or float32.
std::string payload(const VoxelGrid& g) {
  if (g.type() == VoxelType::float32)
    return std::string(reinterpret_cast<const char*>(g.floats().data()), g.floats().size() * sizeof(float));
  return std::string(reinterpret_cast<const char*>(g.bytes().data()), g.bytes().size());
}

// Fills a grid from uint8 or float32 bytes; checks the size first.
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

std::string attribute(const std::string& xml, std::size_t from, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t a = xml.find(key, from);
  if (a == std::string::npos) return "";
  const std::size_t b = xml.find('"', a + key.size());
  return b == std::string::npos ? "" : xml.substr(a + key.size(), b - a - key.size());
}

void put32(std::string& s, std::uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }
std::uint32_t get32(const std::string& s, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

}  // namespace

const char* voxel_formats() { return ".binvox, .raw, .nrrd, .vti, .vox, .vdb"; }

bool is_voxel_format(const std::filesystem::path& path) {
  const std::string e = ext_of(path);
  return e == ".binvox" || e == ".raw" || e == ".nrrd" || e == ".vti" || e == ".vox" || e == ".vdb";
}

// ---- binvox -----------------------------------------------------------------

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

// ---- NRRD -------------------------------------------------------------------

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

// ---- VTK XML ImageData --------------------------------------------------------

std::string encode_vti(const VoxelGrid& g) {
  const auto d = g.dims();
  const double s = g.voxel_size();
  const Vec3 o = g.origin();
  const bool f = g.type() == VoxelType::float32;
  const std::string extent = "0 " + std::to_string(d[0]) + " 0 " + std::to_string(d[1]) + " 0 " + std::to_string(d[2]);
  std::string out =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
      "  <ImageData WholeExtent=\"" +
      extent + "\" Origin=\"" + num(o.x) + " " + num(o.y) + " " + num(o.z) + "\" Spacing=\"" + num(s) + " " + num(s) +
      " " + num(s) +
      "\">\n"
      "    <Piece Extent=\"" +
      extent +
      "\">\n"
      "      <CellData Scalars=\"value\">\n"
      "        <DataArray type=\"" +
      (f ? "Float32" : "UInt8") +
      "\" Name=\"value\" NumberOfComponents=\"1\" format=\"appended\" offset=\"0\"/>\n"
      "      </CellData>\n"
      "    </Piece>\n"
      "  </ImageData>\n"
      "  <AppendedData encoding=\"raw\">\n   _";
  const std::string data = payload(g);
  const std::uint64_t n = data.size();
  out.append(reinterpret_cast<const char*>(&n), 8);
  out += data;
  out += "\n  </AppendedData>\n</VTKFile>\n";
  return out;
}

VoxelGrid decode_vti(const std::string& bytes, const std::string& name) {
  const std::size_t file = bytes.find("<VTKFile");
  if (file == std::string::npos || attribute(bytes, file, "type") != "ImageData")
    bad(name, "not a VTK ImageData file", 0);
  const std::size_t app = bytes.find("<AppendedData");
  const std::string head = bytes.substr(0, app == std::string::npos ? bytes.size() : app);
  const std::size_t image = head.find("<ImageData");
  if (image == std::string::npos) bad(name, "no <ImageData> element");
  const std::vector<double> ext = numbers_in(attribute(head, image, "WholeExtent"));
  const std::vector<double> org = numbers_in(attribute(head, image, "Origin"));
  const std::vector<double> spc = numbers_in(attribute(head, image, "Spacing"));
  if (ext.size() != 6 || org.size() != 3 || spc.size() != 3) bad(name, "WholeExtent, Origin or Spacing is missing");
  const bool cells = head.find("<CellData") != std::string::npos &&
                     head.find("<DataArray", head.find("<CellData")) < head.find("</CellData>");
  // Point data holds one more sample than cells along each axis.
  const int sub = cells ? 0 : 1;
  const auto d = checked_text_dims(ext[1] - ext[0] + sub, ext[3] - ext[2] + sub, ext[5] - ext[4] + sub, name);
  const std::size_t arr = head.find("<DataArray");
  if (arr == std::string::npos) bad(name, "no <DataArray>");
  const std::string type = attribute(head, arr, "type"), format = attribute(head, arr, "format");
  VoxelType t;
  if (type == "UInt8") t = VoxelType::uint8;
  else if (type == "Float32") t = VoxelType::float32;
  else bad(name, "DataArray type '" + type + "' is not read (UInt8 or Float32)");
  if (format != "appended" || app == std::string::npos) bad(name, "only appended raw data is read");
  if (attribute(bytes, app, "encoding") != "raw") bad(name, "only raw appended data is read (not base64)");
  const bool u64 = attribute(bytes, file, "header_type") == "UInt64";
  const std::size_t underscore = bytes.find('_', app);
  if (underscore == std::string::npos) bad(name, "no '_' before the appended data");
  const std::size_t offset = std::size_t(
      numbers_in(attribute(head, arr, "offset")).empty() ? 0 : numbers_in(attribute(head, arr, "offset"))[0]);
  std::size_t at = underscore + 1 + offset;
  const std::size_t hsize = u64 ? 8 : 4;
  if (at + hsize > bytes.size()) bad(name, "the appended data is cut short", at);
  std::uint64_t n = 0;
  std::memcpy(&n, bytes.data() + at, hsize);
  at += hsize;
  const Vec3 o{org[0] + ext[0] * spc[0], org[1] + ext[2] * spc[1], org[2] + ext[4] * spc[2]};
  // Point samples sit at voxel centres: the grid starts half a voxel before.
  const Vec3 origin = cells ? o : o - Vec3{0.5, 0.5, 0.5} * spc[0];
  VoxelGrid g = make_grid(d, origin, spc[0], t, name, bytes.size() - at);
  fill(g, bytes.data() + at, std::min<std::size_t>(n, bytes.size() - at), name, at);
  return g;
}

// ---- MagicaVoxel ----------------------------------------------------------------

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

// ---- files ------------------------------------------------------------------------

void write_voxel_grid(const VoxelGrid& g, const std::filesystem::path& path) {
  const std::string e = ext_of(path);
  if (e == ".binvox") write_file_bytes(path, encode_binvox(g));
  else if (e == ".nrrd") write_file_bytes(path, encode_nrrd(g));
  else if (e == ".vti") write_file_bytes(path, encode_vti(g));
  else if (e == ".vox") write_file_bytes(path, encode_vox(g));
  else if (e == ".vdb") write_vdb(g, path);
  else if (e == ".raw") {
    const auto d = g.dims();
    const Vec3 o = g.origin();
    nlohmann::json j = {{"format", "cgview-raw-voxels"},
                        {"version", 1},
                        {"data_file", path.filename().string()},
                        {"dims", {d[0], d[1], d[2]}},
                        {"origin", {o.x, o.y, o.z}},
                        {"voxel_size", g.voxel_size()},
                        {"type", g.type() == VoxelType::bit     ? "bit"
                                 : g.type() == VoxelType::uint8 ? "uint8"
                                                                : "float32"},
                        {"bytes_per_voxel", g.type() == VoxelType::float32 ? 4 : 1},
                        {"order", "x fastest, then y, then z"},
                        {"endian", "little"},
                        {"origin_is", "the corner of voxel (0, 0, 0)"}};
    write_file_bytes(path, payload(g));
    write_file_bytes(path.string() + ".json", j.dump(2) + "\n");
  } else {
    throw UnsupportedFormat("a voxel grid cannot be saved as '" + e + "' (use " + voxel_formats() + " or .vtk)");
  }
}

VoxelGrid read_voxel_grid(const std::filesystem::path& path) {
  const std::string e = ext_of(path), name = path.string();
  if (!is_voxel_format(path))
    throw UnsupportedFormat("'" + e + "' is not a voxel format CGView reads (use " + voxel_formats() + ")");
  if (e == ".vdb") return read_vdb(path);
  if (e == ".raw") {
    const std::string side = read_file_bytes(path.string() + ".json", 1 << 20);
    nlohmann::json j;
    try {
      j = parse_json(side, name + ".json");
      const auto d = checked_dims(j.at("dims").at(0).get<long long>(), j.at("dims").at(1).get<long long>(),
                                  j.at("dims").at(2).get<long long>(), name + ".json");
      const std::string type = j.at("type").get<std::string>();
      const VoxelType t = type == "bit"       ? VoxelType::bit
                          : type == "uint8"   ? VoxelType::uint8
                          : type == "float32" ? VoxelType::float32
                                              : throw ParseError(name + ".json", "unknown type '" + type + "'",
                                                                 std::nullopt, std::nullopt);
      const Vec3 o{j.at("origin").at(0).get<double>(), j.at("origin").at(1).get<double>(),
                   j.at("origin").at(2).get<double>()};
      const std::string data = read_file_bytes(path, kMaxRead);
      VoxelGrid g = make_grid(d, o, j.at("voxel_size").get<double>(), t, name, data.size());
      fill(g, data.data(), data.size(), name, 0);
      return g;
    } catch (const nlohmann::json::exception& ex) {
      bad(name + ".json", std::string("a malformed sidecar: ") + ex.what());
    }
  }
  const std::string bytes = read_file_bytes(path, kMaxRead);
  if (e == ".binvox") return decode_binvox(bytes, name);
  if (e == ".nrrd") return decode_nrrd(bytes, name);
  if (e == ".vti") return decode_vti(bytes, name);
  if (e == ".vox") return decode_vox(bytes, name);
  throw UnsupportedFormat("'" + e + "' is not a voxel format CGView reads (use " + voxel_formats() + ")");
}

}  // namespace cgview
