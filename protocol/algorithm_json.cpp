#include "algorithm_json.h"

#include <nlohmann/json.hpp>

namespace cgview::protocol {

using nlohmann::json;

namespace {
json value_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}
}  // namespace

json to_json(const Algorithm& a) {
  json props = json::object();
  for (const ParamSpec& p : a.params) {
    json s;
    switch (p.type) {
      case ParamType::integer:
        s["type"] = "integer";
        break;
      case ParamType::number:
        s["type"] = "number";
        break;
      case ParamType::boolean:
        s["type"] = "boolean";
        break;
      case ParamType::choice:
        s["type"] = "string";
        s["enum"] = p.info.choices;
        break;
      case ParamType::text:
        s["type"] = "string";
        break;
      case ParamType::faces:
      case ParamType::vertices:
        // A selection of the first input mesh: the viewer offers its current one.
        s["type"] = "array";
        s["items"] = {{"type", "integer"}, {"minimum", 0}};
        s["uniqueItems"] = true;
        s["x-cgview-selection"] = to_string(p.type);
        break;
    }
    s["title"] = p.info.label;
    if (!p.info.help.empty()) s["description"] = p.info.help;
    s["default"] = value_json(p.default_value);
    if (p.info.min) s["minimum"] = *p.info.min;
    if (p.info.max) s["maximum"] = *p.info.max;
    props[p.name] = s;
  }
  json inputs = json::array();
  for (const InputSpec& in : a.info.inputs)
    inputs.push_back({{"name", in.name}, {"kind", to_string(in.kind)}, {"description", in.help}});
  json outputs = json::array();
  for (const auto& [name, kind] : a.info.outputs) outputs.push_back({{"name", name}, {"kind", to_string(kind)}});
  return {{"name", a.info.name},
          {"title", a.info.title},
          {"description", a.info.description},
          {"area", a.info.area},
          {"inputs", inputs},
          {"outputs", outputs},
          {"params", {{"type", "object"}, {"properties", props}, {"additionalProperties", false}}}};
}

std::map<std::string, ParamValue> params_from_json(const Algorithm& a, const json& params) {
  std::map<std::string, ParamValue> out;
  if (params.is_null()) return out;
  if (!params.is_object()) throw InvalidInput("\"params\" must be a JSON object");
  for (const auto& [name, v] : params.items()) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : a.params)
      if (s.name == name) spec = &s;
    if (!spec) {
      std::string list;
      for (const auto& s : a.params) list += (list.empty() ? "" : ", ") + s.name;
      throw InvalidInput("algorithm '" + a.info.name + "' has no parameter '" + name + "'" +
                         (list.empty() ? " (it takes none)" : " (it takes: " + list + ")"));
    }
    ParamValue value;
    if (v.is_boolean()) value = v.get<bool>();
    else if (v.is_number_integer()) value = v.get<long long>();
    else if (v.is_number()) value = v.get<double>();
    else if (v.is_string()) value = v.get<std::string>();
    else if (v.is_array() && is_selection(spec->type)) {
      Ids ids;
      for (const auto& e : v) {
        if (!e.is_number_integer() || e.get<long long>() < 0 || e.get<long long>() > 0xffffffffLL)
          throw InvalidInput("parameter '" + name + "': ids must be non-negative integers, got " + e.dump());
        ids.push_back(Index(e.get<long long>()));
      }
      value = std::move(ids);
    } else
      throw InvalidInput("parameter '" + name + "': must be a " + std::string(to_string(spec->type)) + ", got " +
                         v.dump());
    out[name] = check_param(*spec, value);
  }
  return out;
}

}  // namespace cgview::protocol
