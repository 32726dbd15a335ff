#include "jobs/artifact_formats.h"

#include <cstring>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "jobs/job_files.h"
#include "io/skeleton_io.h"
#include "registry/artifact_io.h"
#include "store.h"
#include "voxel/voxel_io.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

ArtifactBytes serve_artifact(const fs::path& dir, const json& entry, const std::string& name, std::string format,
                             const std::function<Mesh()>& input_mesh) {
  const std::string kind = entry.value("kind", "");
  const std::string file = entry.value("file", "");
  for (char& c : format) c = char(std::tolower(static_cast<unsigned char>(c)));
  ArtifactBytes out;
  out.content_type = "application/octet-stream";
  if (kind == "scalar_field") {
    if (format.empty()) format = "json";
    const std::string raw = read_job_file(dir / file);
    if (format == "f32") {
      out.bytes = raw;
    } else {
      ScalarField field;
      field.name = name;
      const json side = parse_json_or_discarded(read_job_file(dir / (name + ".field.json")));
      if (side.is_object()) field.name = side.value("name", name);
      field.location = entry.value("location", "vertex") == "face" ? Location::face : Location::vertex;
      const std::string hint = entry.value("hint", "standard");
      field.hint = hint == "symmetric"     ? ColorHint::symmetric
                   : hint == "magnitude"   ? ColorHint::magnitude
                   : hint == "categorical" ? ColorHint::categorical
                                           : ColorHint::standard;
      field.values.resize(raw.size() / sizeof(float));
      std::memcpy(field.values.data(), raw.data(), field.values.size() * sizeof(float));
      if (format == "json") {
        const auto [lo, hi] = field.range();
        json values = json::array();
        for (float v : field.values) values.push_back(v);
        out.bytes = json{
            {"name", field.name},
            {"location", to_string(field.location)},
            {"hint", to_string(field.hint)},
            {"range", {lo, hi}},
            {"values",
             values}}.dump();
        out.content_type = "application/json";
      } else if (format == "txt" || format == "csv" || format == "ply") {
        Mesh input;
        if (format == "ply") {
          input = input_mesh();
        }
        const fs::path tmp = dir / ("tmp-" + new_id() + "." + format);
        try {
          write_artifact(Artifact{name, field}, input, tmp);
          out.bytes = read_job_file(tmp);
        } catch (...) {
          std::error_code ec;
          fs::remove(tmp, ec);
          throw;
        }
        std::error_code ec;
        fs::remove(tmp, ec);
        if (format != "ply") out.content_type = format == "csv" ? "text/csv" : "text/plain; charset=utf-8";
      } else {
        throw UnsupportedFormat("a scalar field is served as txt, csv, ply, json or f32, not '" + format + "'");
      }
    }
  } else if (kind == "mesh") {
    if (format.empty() || format == "ply") {
      out.bytes = read_job_file(dir / file);
      format = "ply";
    } else {
      const MeshFormat f = format_from_name("x." + format);
      if (!can_write(f)) throw UnsupportedFormat("a mesh cannot be served as '" + format + "'");
      out.bytes = write_mesh_bytes(read_mesh_file(dir / file).mesh, f);
    }
  } else if (kind == "metrics") {
    if (!format.empty() && format != "json")
      throw UnsupportedFormat("metrics are served as json, not '" + format + "'");
    format = "json";
    out.bytes = read_job_file(dir / file);
    out.content_type = "application/json";
  } else if (kind == "voxel_grid") {
    const std::string ext = fs::path(file).extension().string().substr(1);
    if (format.empty()) format = ext;
    if (format == ext) {
      out.bytes = read_job_file(dir / file);
    } else {
      const VoxelGrid grid = read_voxel_grid(dir / file);
      if (format == "nrrd") out.bytes = encode_nrrd(grid);
      else if (format == "binvox") out.bytes = encode_binvox(grid);
      else if (format == "vti") out.bytes = encode_vti(grid);
      else if (format == "vox") out.bytes = encode_vox(grid);
      else throw UnsupportedFormat("a voxel grid is served as nrrd, binvox, vti or vox, not '" + format + "'");
    }
  } else if (kind == "skeleton") {
    // Stored as .obj; also served in the other skeleton files (io/skeleton_io.h).
    if (format.empty()) format = "obj";
    const std::string stored = read_job_file(dir / file);
    if (format == "obj") {
      out.bytes = stored;
    } else {
      if (format != "cg" && format != "json" && format != "polylines")
        throw UnsupportedFormat("a skeleton is served as obj, cg, json or polylines, not '" + format + "'");
      const SkeletonFormat f =
          skeleton_format_from_name("s." + std::string(format == "polylines" ? "polylines.txt" : format));
      out.bytes = write_skeleton_bytes(read_skeleton_bytes(stored, SkeletonFormat::obj, file), f);
      if (format == "polylines") format = "polylines.txt";
    }
    out.content_type = format == "json" ? "application/json" : "text/plain; charset=utf-8";
  } else {
    const std::string ext = fs::path(file).extension().string().substr(1);
    if (!format.empty() && format != ext)
      throw UnsupportedFormat("a " + kind + " is served as " + ext + ", not '" + format + "'");
    format = ext;
    out.bytes = read_job_file(dir / file);
  }
  out.file_name = name + "." + format;
  return out;
}

}  // namespace cgview::server
