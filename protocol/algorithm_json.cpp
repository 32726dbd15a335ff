#include "algorithm_json.h"

#include <algorithm>

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
  json order = json::array();  // the properties come sorted by name: forms follow the declared order
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
    if (p.info.advanced) s["x-cgview-advanced"] = true;
    if (!p.info.when.param.empty()) s["x-cgview-when"] = {{"param", p.info.when.param}, {"in", p.info.when.values}};
    props[p.name] = s;
    order.push_back(p.name);
  }
  json inputs = json::array();
  for (const InputSpec& in : a.info.inputs) {
    inputs.push_back({{"name", in.name}, {"kind", to_string(in.kind)}, {"description", in.help}});
    if (in.faceless) inputs.back()["faceless"] = true;
  }
  json outputs = json::array();
  for (const auto& [name, kind] : a.info.outputs) outputs.push_back({{"name", name}, {"kind", to_string(kind)}});
  return {{"name", a.info.name},
          {"title", a.info.title},
          {"description", a.info.description},
          {"area", a.info.area},
          {"inputs", inputs},
          {"outputs", outputs},
          {"params",
           {{"type", "object"}, {"properties", props}, {"additionalProperties", false}, {"x-cgview-order", order}}}};
}

namespace {

OutputKind kind_from(const std::string& k) {
  for (OutputKind o : kOutputKinds)
    if (k == to_string(o)) return o;
  throw InvalidInput("an algorithm's description names no kind '" + k + "'");
}

ParamValue value_from(const json& v) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number_integer()) return v.get<long long>();
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    Ids ids;
    for (const auto& e : v)
      if (e.is_number_unsigned()) ids.push_back(Index(e.get<unsigned long long>()));
    return ids;
  }
  throw InvalidInput("an algorithm's description has a default of no known type: " + v.dump());
}

}  // namespace

Algorithm algorithm_from_json(const json& d) {
  if (!d.is_object() || !d.value("name", json()).is_string())
    throw InvalidInput("an algorithm's description must be an object with a name");
  Algorithm a;
  a.info.name = d["name"];
  a.info.title = d.value("title", "");
  a.info.description = d.value("description", "");
  a.info.area = d.value("area", "");
  a.info.inputs.clear();
  for (const auto& in : d.value("inputs", json::array()))
    a.info.inputs.push_back({.name = in.value("name", ""),
                             .kind = kind_from(in.value("kind", "mesh")),
                             .help = in.value("description", ""),
                             .faceless = in.value("faceless", false)});
  for (const auto& out : d.value("outputs", json::array()))
    a.info.outputs.emplace_back(out.value("name", ""), kind_from(out.value("kind", "")));
  const json params = d.value("params", json::object());
  const json props = params.value("properties", json::object());
  // The declared order where the description gives it, then the rest by name.
  std::vector<std::string> names;
  for (const auto& n : params.value("x-cgview-order", json::array()))
    if (n.is_string() && props.contains(n.get<std::string>()) &&
        std::find(names.begin(), names.end(), n.get<std::string>()) == names.end())
      names.push_back(n);
  for (const auto& [name, s] : props.items())
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  for (const std::string& name : names) {
    const json& s = props[name];
    ParamSpec p;
    p.name = name;
    const std::string type = s.value("type", "");
    if (s.contains("x-cgview-selection"))
      p.type = s["x-cgview-selection"] == "vertices" ? ParamType::vertices : ParamType::faces;
    else if (type == "integer") p.type = ParamType::integer;
    else if (type == "number") p.type = ParamType::number;
    else if (type == "boolean") p.type = ParamType::boolean;
    else if (type == "string" && s.contains("enum")) p.type = ParamType::choice;
    else if (type == "string") p.type = ParamType::text;
    else throw InvalidInput("parameter '" + name + "' of the description has no known type");
    p.default_value = value_from(s.value("default", json()));
    if (p.type == ParamType::number && std::holds_alternative<long long>(p.default_value))
      p.default_value = double(std::get<long long>(p.default_value));
    p.info.label = s.value("title", name);
    p.info.help = s.value("description", "");
    if (s.contains("minimum")) p.info.min = s["minimum"].get<double>();
    if (s.contains("maximum")) p.info.max = s["maximum"].get<double>();
    if (s.contains("enum")) p.info.choices = s["enum"].get<std::vector<std::string>>();
    p.info.advanced = s.value("x-cgview-advanced", false);
    if (const json w = s.value("x-cgview-when", json()); w.is_object()) {
      p.info.when.param = w.value("param", "");
      p.info.when.values = w.value("in", std::vector<std::string>{});
    }
    a.params.push_back(std::move(p));
  }
  check_conditions(a.params);
  return a;
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
