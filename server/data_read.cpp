#include "data_read.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "artifacts/artifact_codec.h"
#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "io/skeleton_io.h"
#include "jobs/artifact_files.h"
#include "voxel/voxel_io.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const char* const kKnown =
    "voxel grids (.nrrd, .binvox, .vti, .vox, .vdb), skeletons (.polylines.txt, .cg, .obj, .json) and scalar fields "
    "(.ply with a per-vertex or per-face property, .txt with one value a line)";

bool is_field_name(const std::string& n) {
  return (n.ends_with(".ply") || n.ends_with(".txt")) && !n.ends_with(".polylines.txt");
}

// An artifact's name from a property's or a file's: letters, digits, '_' and '-'.
std::string artifact_name(const std::string& from, const std::string& fallback) {
  std::string s;
  for (char c : from.substr(0, 64)) s += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
  return s.empty() || s.find_first_not_of('_') == std::string::npos ? fallback : s;
}

VoxelGrid read_grid(const std::string& name, std::string_view bytes, const fs::path& scratch) {
  const std::string n = ascii_lower(name);
  const std::string b(bytes);
  if (n.ends_with(".nrrd")) return decode_nrrd(b, name);
  if (n.ends_with(".binvox")) return decode_binvox(b, name);
  if (n.ends_with(".vti")) return decode_vti(b, name);
  if (n.ends_with(".vox")) return decode_vox(b, name);
  // OpenVDB reads files only.
  const fs::path p = scratch / "upload-grid.vdb";
  write_file_bytes(p, bytes);
  try {
    VoxelGrid g = read_vdb(p);
    fs::remove(p);
    return g;
  } catch (...) {
    std::error_code ec;
    fs::remove(p, ec);
    throw;
  }
}

// One value a line; blank lines skipped; "nan" is a value missing.
std::vector<float> read_values(const std::string& name, std::string_view text) {
  std::vector<float> values;
  std::size_t line = 0;
  while (!text.empty()) {
    ++line;
    const std::size_t nl = text.find('\n');
    std::string l(text.substr(0, nl));
    text.remove_prefix(nl == std::string_view::npos ? text.size() : nl + 1);
    while (!l.empty() && std::isspace(static_cast<unsigned char>(l.back()))) l.pop_back();
    std::size_t start = 0;
    while (start < l.size() && std::isspace(static_cast<unsigned char>(l[start]))) ++start;
    if (start == l.size()) continue;
    char* end = nullptr;
    const double v = std::strtod(l.c_str() + start, &end);
    if (end == l.c_str() + start || *end != '\0')
      throw ParseError(name, "'" + l.substr(start, 40) + "' is not a number (one value a line)", line, std::nullopt);
    if (std::isinf(v) || (std::isfinite(v) && std::abs(v) > std::numeric_limits<float>::max()))
      throw ParseError(name, "a value too large for a float", line, std::nullopt);
    values.push_back(float(v));
  }
  return values;
}

ScalarField read_field(const DataRequest& req, std::string_view bytes, std::vector<std::string>& warnings) {
  if (!req.for_mesh) throw InvalidInput(req.name + ": a scalar field is uploaded for a stored mesh: add ?mesh=ID");
  const std::string n = ascii_lower(req.name);
  ScalarField f;
  f.name = artifact_name(fs::path(req.name).stem().string(), "field");
  bool location_known = false;
  if (n.ends_with(".ply")) {
    ReadResult r = read_mesh_bytes(bytes, MeshFormat::ply, req.name);
    if (r.properties.empty())
      throw InvalidInput(req.name +
                         ": its vertices and faces carry no scalar property (positions, normals, colours and texture "
                         "coordinates are the mesh's own)");
    auto chosen = r.properties.begin();
    if (!req.property.empty()) {
      chosen = std::find_if(r.properties.begin(), r.properties.end(),
                            [&](const ScalarField& p) { return p.name == req.property; });
      if (chosen == r.properties.end()) {
        std::string names;
        for (const ScalarField& p : r.properties) names += (names.empty() ? "" : ", ") + p.name;
        throw InvalidInput(req.name + " has no property '" + req.property + "' (it has " + names + ")");
      }
    }
    std::string others;
    for (const ScalarField& p : r.properties)
      if (&p != &*chosen) others += (others.empty() ? "" : ", ") + p.name;
    if (!others.empty())
      warnings.push_back("the file's other properties were not used: " + others +
                         " (upload it again with ?property=NAME for one of them)");
    warnings.push_back("the file's own vertices and faces were not used: the field is shown on the stored mesh");
    f.values = std::move(chosen->values);
    f.location = chosen->location;
    f.name = artifact_name(chosen->name, "field");
    location_known = true;
  } else {
    f.values = read_values(req.name, bytes);
  }
  const std::size_t count = f.values.size();
  const std::string counts =
      std::to_string(req.mesh_vertices) + " vertices and " + std::to_string(req.mesh_faces) + " faces";
  if (location_known) {
    const std::size_t want = f.location == Location::vertex ? req.mesh_vertices : req.mesh_faces;
    if (count != want)
      throw InvalidInput(req.name + ": " + std::to_string(count) + " per-" + to_string(f.location) +
                         " values, but the mesh has " + counts);
  } else if (count == req.mesh_vertices) {
    f.location = Location::vertex;
    if (count == req.mesh_faces)
      warnings.push_back("the mesh has as many vertices as faces: the values were taken as one per vertex");
  } else if (count == req.mesh_faces) {
    f.location = Location::face;
  } else {
    throw InvalidInput(req.name + ": " + std::to_string(count) + " values, but the mesh has " + counts +
                       " (one value per vertex, or per face)");
  }
  const auto missing = std::count_if(f.values.begin(), f.values.end(), [](float v) { return std::isnan(v); });
  if (missing)
    warnings.push_back(std::to_string(missing) + " of the " + std::to_string(count) +
                       " values are missing (nan): those " + (f.location == Location::vertex ? "vertices" : "faces") +
                       " show no colour");
  return f;
}

}  // namespace

std::string data_kind(const std::string& name, const std::string& kind) {
  const std::string n = ascii_lower(name);
  if (n.ends_with(".raw"))
    throw UnsupportedFormat(name +
                            ": a .raw grid needs its .json beside it, which one upload cannot carry: upload the grid "
                            "as .nrrd, .vti, .binvox, .vox or .vdb");
  const bool grid = is_voxel_format(n), skeleton = is_skeleton_file_name(n), field = is_field_name(n);
  if (kind.empty()) {
    if (grid) return "voxel_grid";
    if (skeleton) return "skeleton";
    if (field) return "scalar_field";
    throw UnsupportedFormat("'" + name + "' is no kind of data this server reads: " + kKnown);
  }
  if ((kind == "voxel_grid" && grid) || (kind == "skeleton" && skeleton) || (kind == "scalar_field" && field))
    return kind;
  if (kind != "voxel_grid" && kind != "skeleton" && kind != "scalar_field")
    throw InvalidInput("kind '" + kind + "' is none of voxel_grid, skeleton and scalar_field");
  throw UnsupportedFormat("a " + kind + " is not read from '" + name + "': " + kKnown);
}

DataRead read_data(const DataRequest& req, std::string_view bytes, const fs::path& out_dir) {
  const std::string kind = data_kind(req.name, req.kind);
  DataRead r;
  if (kind == "voxel_grid") {
    const Artifact a{"grid", read_grid(req.name, bytes, out_dir)};
    r.entry = artifact_codec(OutputKind::voxel_grid).store(a, Mesh{}, out_dir);
  } else if (kind == "skeleton") {
    const Artifact a{"skeleton", read_skeleton_bytes(bytes, skeleton_format_from_name(req.name), req.name)};
    r.entry = artifact_codec(OutputKind::skeleton).store(a, Mesh{}, out_dir);
  } else {
    const Artifact a{"", read_field(req, bytes, r.warnings)};
    r.entry =
        artifact_codec(OutputKind::scalar_field).store({std::get<ScalarField>(a.value).name, a.value}, Mesh{}, out_dir);
  }
  return r;
}

DataRead read_data_in_child(const UploadReader& reader, const DataRequest& req, std::string_view bytes,
                            const fs::path& out_dir) {
  const std::string n = clean_upload_name(req.name);
  const std::string kind = data_kind(n, req.kind);  // refused here, before a child starts
  ReadDir dir(reader.temp_dir);
  write_file_bytes(dir.path() / "upload", bytes);
  write_file_bytes(dir.path() / "request.json", json{{"name", n},
                                                     {"kind", kind},
                                                     {"property", req.property},
                                                     {"for_mesh", req.for_mesh},
                                                     {"mesh_vertices", req.mesh_vertices},
                                                     {"mesh_faces", req.mesh_faces}}
                                                    .dump());
  run_reader_child(reader, "--read-data", n, dir);
  // What the child wrote is as untrusted as the upload: its shape is checked,
  // and only plain files of its output directory are taken.
  DataRead out;
  try {
    const json r = parse_json_or_discarded(child_file(dir, "result.json", std::size_t(64) << 20));
    if (!r.is_object()) throw std::runtime_error("not an object");
    out.entry = r.at("entry");
    if (!out.entry.is_object() || out.entry.value("kind", "") != kind) throw std::runtime_error("not its kind");
    for (const auto& w : r.at("warnings")) out.warnings.push_back(w.get<std::string>());
  } catch (const std::exception& e) {
    throw InvalidInput(n + ": the upload's reader gave an unreadable result (" + e.what() + ")");
  }
  // Only the regular files the entry names are taken (copied through no
  // link, capped by the sizes its entry states); the rest stays behind.
  fs::create_directories(out_dir);
  const JobDir child_out(dir.path() / "out");
  if (const std::string broken = incomplete_artifact(child_out, json::array({out.entry})); !broken.empty())
    throw InvalidInput(n + ": " + broken);
  if (const std::string refused = take_artifacts(child_out, json::array({out.entry}), out_dir); !refused.empty())
    throw InvalidInput(n + ": " + refused);
  return out;
}

int read_data_main(const fs::path& dir) {
  return reader_main(dir, [&] {
    const json req = json::parse(read_file_bytes(dir / "request.json", 1 << 20));
    DataRequest r;
    r.name = req.at("name").get<std::string>();
    r.kind = req.at("kind").get<std::string>();
    r.property = req.at("property").get<std::string>();
    r.for_mesh = req.at("for_mesh").get<bool>();
    r.mesh_vertices = req.at("mesh_vertices").get<std::size_t>();
    r.mesh_faces = req.at("mesh_faces").get<std::size_t>();
    const std::string bytes = read_file_bytes(dir / "upload", std::numeric_limits<std::size_t>::max());
    fs::create_directories(dir / "out");
    const DataRead d = read_data(r, bytes, dir / "out");
    // result.json last (written through a rename): its presence means the rest is whole.
    write_file_bytes(dir / "result.json", json{{"entry", d.entry}, {"warnings", d.warnings}}.dump());
  });
}

}  // namespace cgview::server
