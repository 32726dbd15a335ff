// A vector field artifact: stored as its raw little-endian float32 x, y, z
// triples (NAME.vec.f32, what the viewer and numpy read directly); the list
// entry carries its location, hint, count and longest vector.  Exported as
// json, csv (index,x,y,z), ply (a point cloud at the vectors' origins with
// the vectors as normals: MeshLab and CloudCompare draw them) or vtk (legacy
// POLYDATA with point vectors: ParaView's Glyph filter draws them).
#include <cstring>
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "core/errors.h"
#include "core/vector_field.h"

namespace cgview {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

void append_vec(std::string& s, const Vec3f& v, char sep) {
  append_shortest(s, v.x);
  s += sep;
  append_shortest(s, v.y);
  s += sep;
  append_shortest(s, v.z);
}

// The origins of a field on a mesh that is not the one it was computed on
// (a PLY or VTK asked for without it) are refused rather than invented.
std::vector<Vec3> origins_on(const Mesh& input, const VectorField& f) {
  f.check_matches(input);
  return vector_origins(input, f.location);
}

std::string ply(const Mesh& input, const VectorField& f) {
  const std::vector<Vec3> at = origins_on(input, f);
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment CGView vector field " + f.name + " (" +
                    to_string(f.location) + ")\nelement vertex " + std::to_string(at.size()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
                    "property float nz\nend_header\n";
  for (std::size_t i = 0; i < at.size(); ++i) {
    const float row[6] = {float(at[i].x), float(at[i].y), float(at[i].z), f.values[i].x, f.values[i].y, f.values[i].z};
    out.append(reinterpret_cast<const char*>(row), sizeof row);
  }
  return out;
}

std::string vtk(const Mesh& input, const VectorField& f) {
  const std::vector<Vec3> at = origins_on(input, f);
  const std::string n = std::to_string(at.size());
  std::string out = "# vtk DataFile Version 3.0\nCGView vector field " + f.name + "\nASCII\nDATASET POLYDATA\nPOINTS " +
                    n + " float\n";
  for (const Vec3& p : at) {
    append_vec(out, Vec3f{float(p.x), float(p.y), float(p.z)}, ' ');
    out += '\n';
  }
  out += "VERTICES " + n + " " + std::to_string(2 * at.size()) + "\n";
  for (std::size_t i = 0; i < at.size(); ++i) out += "1 " + std::to_string(i) + "\n";
  // VTK's array names take no spaces.
  std::string array = f.name.empty() ? "vectors" : f.name;
  for (char& c : array)
    if (c == ' ' || c == '\t') c = '_';
  out += "POINT_DATA " + n + "\nVECTORS " + array + " float\n";
  for (const Vec3f& v : f.values) {
    append_vec(out, v, ' ');
    out += '\n';
  }
  return out;
}

class VectorFieldCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::vector_field; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {{"f32", ".vec.f32", "application/octet-stream", true, false},
                                                  {"json", ".json", "application/json", true, false},
                                                  {"csv", ".csv", "text/csv"},
                                                  {"ply", ".ply", "application/octet-stream"},
                                                  {"vtk", ".vtk", "text/plain; charset=utf-8"}};
    return f;
  }
  // Served with its name, location and hint, as the viewer reads it.
  std::string served_default() const override { return "json"; }
  // `cgview run` writes a field for people and spreadsheets.
  std::string default_extension() const override { return ".csv"; }
  bool needs_mesh(const ArtifactFormat& f) const override { return f.name == "ply" || f.name == "vtk"; }

  std::string encode(const ArtifactValue& value, const std::string&, const Mesh& input,
                     const ArtifactFormat& format) const override {
    const VectorField& f = std::get<VectorField>(value);
    if (format.name == "f32")
      return std::string(reinterpret_cast<const char*>(f.values.data()), f.values.size() * sizeof(Vec3f));
    if (format.name == "ply") return ply(input, f);
    if (format.name == "vtk") return vtk(input, f);
    if (format.name == "json") {
      json values = json::array();
      for (const Vec3f& v : f.values) values.push_back({v.x, v.y, v.z});  // NaN (no value) becomes null
      return json{{"name", f.name},
                  {"location", to_string(f.location)},
                  {"hint", to_string(f.hint)},
                  {"max_length", f.max_length()},
                  {"values", values}}
          .dump();
    }
    std::string out = std::string(to_string(f.location)) + ",x,y,z\n";
    for (std::size_t i = 0; i < f.values.size(); ++i) {
      out += std::to_string(i) + ",";
      append_vec(out, f.values[i], ',');
      out += '\n';
    }
    return out;
  }

  ArtifactValue decode(std::string_view stored, const std::string& name, const json& entry) const override {
    if (stored.size() % sizeof(Vec3f) != 0)
      throw ParseError(name + ".vec.f32", std::to_string(stored.size()) + " bytes are not whole float32 triples",
                       std::nullopt, stored.size());
    VectorField f;
    f.name = entry.value("field", name);
    f.location = entry.value("location", "vertex") == "face" ? Location::face : Location::vertex;
    f.hint = entry.value("hint", "arrow") == "direction" ? VectorHint::direction : VectorHint::arrow;
    f.values.resize(stored.size() / sizeof(Vec3f));
    std::memcpy(f.values.data(), stored.data(), stored.size());
    return f;
  }

  json store(const Artifact& a, const Mesh& input, const fs::path& dir) const override {
    json entry = ArtifactCodec::store(a, input, dir);
    const VectorField& f = std::get<VectorField>(a.value);
    entry["field"] = f.name;
    entry["location"] = to_string(f.location);
    entry["hint"] = to_string(f.hint);
    entry["count"] = f.values.size();
    entry["max_length"] = f.max_length();
    return entry;
  }
};

}  // namespace

const ArtifactCodec& vector_field_codec() {
  static const VectorFieldCodec codec;
  return codec;
}

}  // namespace cgview
