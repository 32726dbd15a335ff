// A done job's artifact served in a format: its stored file as it is, or
// converted (a scalar field as json, txt, csv, f32 or a PLY of its mesh; a
// mesh in any writable format; a voxel grid as nrrd, binvox, vti or vox; a
// skeleton as obj, cg, json or polylines).
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "core/mesh.h"

namespace cgview::server {

struct ArtifactBytes {
  std::string bytes, content_type, file_name;
};

// `dir`: the directory holding the artifact's files; `entry`: its entry in
// the worker's list; `format`: "" for its stored form; `input_mesh`: the
// job's mesh (for a field's PLY).  Throws UnsupportedFormat.
ArtifactBytes serve_artifact(const std::filesystem::path& dir, const nlohmann::json& entry, const std::string& name,
                             std::string format, const std::function<Mesh()>& input_mesh);

}  // namespace cgview::server
