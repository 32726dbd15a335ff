#include "mesh_json.h"

namespace cgview::protocol {

namespace {
nlohmann::json mesh_head(const MeshRecord& r) {
  return {{"id", r.id},           {"name", r.name},     {"format", r.format}, {"bytes", r.bytes},
          {"created", r.created}, {"sha256", r.sha256}, {"owner", r.owner}};
}
}  // namespace

nlohmann::json material_of(const MeshRecord& r) {
  nlohmann::json m = nlohmann::json::parse(r.material_json, nullptr, false);
  if (!m.is_object()) m = nlohmann::json::object();
  if (!m.contains("has_uvs")) m["has_uvs"] = false;
  if (!m.contains("textures")) m["textures"] = nlohmann::json::array();
  return m;
}

// The report's "points" (a point cloud: points and no faces), found without
// parsing it: the server writes the report (mesh_report_json.cpp) compact.
bool is_point_cloud(const MeshRecord& r) { return r.report_json.find("\"points\":true") != std::string::npos; }

nlohmann::json mesh_json(const MeshRecord& r) {
  nlohmann::json j = mesh_head(r);
  j["points"] = is_point_cloud(r);
  j["report"] = nlohmann::json::parse(r.report_json);
  j["warnings"] = nlohmann::json::parse(r.warnings_json);
  j.update(material_of(r));
  return j;
}

std::string mesh_json_text(const MeshRecord& r) {
  nlohmann::json head = mesh_head(r);
  head["points"] = is_point_cloud(r);
  std::string s = head.dump();
  s.pop_back();                           // the closing brace
  std::string m = material_of(r).dump();  // {"has_uvs":...}: spliced in without its braces
  return s + ",\"report\":" + r.report_json + ",\"warnings\":" + r.warnings_json + "," + m.substr(1);
}

}  // namespace cgview::protocol
