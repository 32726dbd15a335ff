// VTK XML ImageData: one cell per voxel, appended raw binary.
#include <algorithm>
#include <cstring>
#include <string>

#include "voxel/voxel_file_parts.h"
#include "voxel/voxel_io.h"

namespace cgview {

using namespace voxel_file;

namespace {

std::string attribute(const std::string& xml, std::size_t from, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const std::size_t a = xml.find(key, from);
  if (a == std::string::npos) return "";
  const std::size_t b = xml.find('"', a + key.size());
  return b == std::string::npos ? "" : xml.substr(a + key.size(), b - a - key.size());
}

}  // namespace

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

}  // namespace cgview
