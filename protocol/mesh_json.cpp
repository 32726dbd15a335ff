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

nlohmann::json mesh_json(const MeshRecord& r) {
  nlohmann::json j = mesh_head(r);
  j["report"] = nlohmann::json::parse(r.report_json);
  j["warnings"] = nlohmann::json::parse(r.warnings_json);
  j.update(material_of(r));
  return j;
}

std::string mesh_json_text(const MeshRecord& r) {
  std::string s = mesh_head(r).dump();
  s.pop_back();                           // the closing brace
  std::string m = material_of(r).dump();  // {"has_uvs":...}: spliced in without its braces
  return s + ",\"report\":" + r.report_json + ",\"warnings\":" + r.warnings_json + "," + m.substr(1);
}

}  // namespace cgview::protocol
