// A stored mesh as the server keeps it and as clients read it
// (GET /api/v1/meshes/ID, protocol/API.md's `Mesh`): its record, and the
// JSON made from it.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

namespace cgview::protocol {

struct MeshRecord {
  std::string id;      // 16 hex digits
  std::string name;    // as uploaded ("elephant.off")
  std::string format;  // "off", "ply", ...
  std::uint64_t bytes = 0;
  std::string sha256;         // of the uploaded bytes
  std::string created;        // ISO 8601 UTC
  std::string report_json;    // protocol::to_json(MeshReport), serialized
  std::string warnings_json;  // JSON array of strings
  std::string owner = "local";
  // JSON object: has_uvs, and textures (one per texture blob: name, mime,
  // bytes, material, kd); "{}" for a mesh stored before textures existed.
  std::string material_json = "{}";
};

// The material part of a mesh's JSON: has_uvs, textures (one per texture
// blob: name, mime, bytes, ...) and, when the material gives them, kd and
// materials; a mesh stored before textures existed reads as untextured.
nlohmann::json material_of(const MeshRecord& record);
// Whether the stored mesh is a point cloud: its report's "points".
bool is_point_cloud(const MeshRecord& record);
// The Mesh clients read: id, name, format, bytes, created, sha256, owner,
// points (true for a point cloud: points and no faces), report, warnings,
// has_uvs, textures.
nlohmann::json mesh_json(const MeshRecord& record);
// The same as text, the stored report and warnings spliced in unparsed (a
// big mesh's report is read often and need not be parsed for it).
std::string mesh_json_text(const MeshRecord& record);

}  // namespace cgview::protocol
