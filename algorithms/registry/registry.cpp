#include "registry/registry.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <list>
#include <sstream>

#include "core/mesh_report.h"
#include "core/orient.h"

namespace cgview {

namespace {
std::map<std::string, Algorithm>& table() {
  static std::map<std::string, Algorithm> t;  // filled during static initialization
  return t;
}

std::string number_text(double d) {
  std::ostringstream s;
  s << d;
  return s.str();
}

[[noreturn]] void bad(const ParamSpec& spec, const std::string& rule) {
  throw InvalidInput("parameter '" + spec.name + "': " + rule);
}
}  // namespace

const std::map<std::string, Algorithm>& algorithms() { return table(); }

const Algorithm& find_algorithm(const std::string& name) {
  const auto it = table().find(name);
  if (it == table().end()) throw std::out_of_range("no algorithm named '" + name + "'");
  return it->second;
}

void detail::set_precheck(const std::string& name,
                          std::function<void(const InputSummaries&, const std::map<std::string, ParamValue>&)> check) {
  const auto it = table().find(name);
  if (it == table().end()) throw std::logic_error("a precheck for '" + name + "', which is not registered (yet)");
  it->second.precheck = std::move(check);
}

namespace {
std::vector<std::string>* registration_clashes = nullptr;
}

void detail::set_registration_clashes(std::vector<std::string>* sink) { registration_clashes = sink; }

void check_conditions(const std::vector<ParamSpec>& specs) {
  for (const ParamSpec& p : specs) {
    const ParamCondition& w = p.info.when;
    if (w.param.empty()) continue;
    const auto on = std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& s) { return s.name == w.param; });
    const std::string what = "parameter '" + p.name + "' applies when '" + w.param + "' ";
    if (on == specs.end() || on->name == p.name) throw InvalidInput(what + "is, but there is no such other parameter");
    if (on->type != ParamType::choice && on->type != ParamType::boolean)
      throw InvalidInput(what + "is, but only a choice or a boolean can say when");
    if (w.values.empty()) throw InvalidInput(what + "has one of no values");
    const std::vector<std::string> can =
        on->type == ParamType::boolean ? std::vector<std::string>{"true", "false"} : on->info.choices;
    for (const std::string& v : w.values)
      if (std::find(can.begin(), can.end(), v) == can.end())
        throw InvalidInput(what + "is '" + v + "', which it cannot be");
  }
}

void register_algorithm(Algorithm a) {
  const std::string name = a.info.name;
  check_conditions(a.params);
  std::vector<std::string> outward;
  for (const InputSpec& in : a.info.inputs)
    if (in.outward && in.kind == OutputKind::mesh) outward.push_back(in.name);
  if (!outward.empty())
    a.run = [run = std::move(a.run), outward, title = a.info.title](
                const Inputs& inputs, const std::map<std::string, ParamValue>& params, Context& ctx) {
      Inputs turned = inputs;
      std::list<Mesh> copies;  // stable addresses for `turned`
      std::vector<std::string> said;
      for (const std::string& in : outward) {
        if (!inputs.has(in) || !mesh_report(inputs.mesh(in)).faces_inward) continue;
        flip_faces(copies.emplace_back(inputs.mesh(in)));
        turned.add(in, copies.back());
        said.push_back("the " + in + " is a closed mesh whose faces all face inward (a negative volume): " + title +
                       " ran on it turned outward; Repair or Orient outward turns the mesh itself");
      }
      AlgorithmResult r = run(copies.empty() ? inputs : turned, params, ctx);
      r.warnings.insert(r.warnings.begin(), said.begin(), said.end());
      return r;
    };
  if (table().emplace(name, std::move(a)).second) return;
  if (registration_clashes) registration_clashes->push_back(name);
  else throw std::logic_error("two algorithms are named '" + name + "'");
}

const char* to_string(ParamType t) {
  switch (t) {
    case ParamType::integer:
      return "integer";
    case ParamType::number:
      return "number";
    case ParamType::boolean:
      return "boolean";
    case ParamType::choice:
      return "choice";
    case ParamType::text:
      return "text";
    case ParamType::faces:
      return "faces";
    case ParamType::vertices:
      return "vertices";
  }
  return "?";
}

bool is_selection(ParamType t) { return t == ParamType::faces || t == ParamType::vertices; }

void check_selections(const std::vector<ParamSpec>& specs, const std::map<std::string, ParamValue>& values,
                      std::size_t vertices, std::size_t faces) {
  for (const ParamSpec& s : specs) {
    if (!is_selection(s.type)) continue;
    const auto it = values.find(s.name);
    if (it == values.end()) continue;
    const auto* ids = std::get_if<Ids>(&it->second);
    if (!ids) continue;  // check_param refuses it
    const bool f = s.type == ParamType::faces;
    const std::size_t n = f ? faces : vertices;
    for (const Index id : *ids)
      if (id >= n)
        bad(s, std::string(f ? "face" : "vertex") + " id " + std::to_string(id) + " is out of range (the mesh has " +
                   std::to_string(n) + (f ? " faces)" : " vertices)"));
  }
}

const char* to_string(OutputKind k) {
  switch (k) {
    case OutputKind::mesh:
      return "mesh";
    case OutputKind::scalar_field:
      return "scalar_field";
    case OutputKind::voxel_grid:
      return "voxel_grid";
    case OutputKind::skeleton:
      return "skeleton";
    case OutputKind::metrics:
      return "metrics";
    case OutputKind::text:
      return "text";
    case OutputKind::animation:
      return "animation";
    case OutputKind::vector_field:
      return "vector_field";
    case OutputKind::points:
      return "points";
  }
  return "?";
}

std::string to_string(const ParamValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
        else if constexpr (std::is_same_v<T, std::string>) return x;
        else if constexpr (std::is_same_v<T, double>) return number_text(x);
        else if constexpr (std::is_same_v<T, Ids>) {
          std::string s;
          for (const Index id : x) {
            if (!s.empty()) s += ',';
            s += std::to_string(id);
          }
          return s;
        } else return std::to_string(x);
      },
      v);
}

ParamValue check_param(const ParamSpec& spec, const ParamValue& value) {
  const ParamInfo& i = spec.info;
  auto check_range = [&](double x) {
    if (i.min && x < *i.min) bad(spec, to_string(value) + " is under the minimum " + number_text(*i.min));
    if (i.max && x > *i.max) bad(spec, to_string(value) + " is over the maximum " + number_text(*i.max));
  };
  switch (spec.type) {
    case ParamType::integer: {
      long long n;
      if (const auto* p = std::get_if<long long>(&value)) n = *p;
      else if (const auto* d = std::get_if<double>(&value);
               d && std::isfinite(*d) && *d == std::floor(*d) && std::fabs(*d) < 9e15)
        n = (long long)*d;
      else bad(spec, "must be an integer, got " + to_string(value));
      check_range(double(n));
      return n;
    }
    case ParamType::number: {
      double d;
      if (const auto* p = std::get_if<double>(&value)) d = *p;
      else if (const auto* n = std::get_if<long long>(&value)) d = double(*n);
      else bad(spec, "must be a number, got " + to_string(value));
      if (!std::isfinite(d)) bad(spec, "must be a finite number");
      check_range(d);
      return d;
    }
    case ParamType::boolean:
      if (!std::holds_alternative<bool>(value)) bad(spec, "must be true or false, got " + to_string(value));
      return value;
    case ParamType::choice: {
      const auto* s = std::get_if<std::string>(&value);
      if (!s) bad(spec, "must be one of its choices, got " + to_string(value));
      for (const auto& c : i.choices)
        if (c == *s) return value;
      std::string list;
      for (const auto& c : i.choices) list += (list.empty() ? "" : ", ") + c;
      bad(spec, "'" + *s + "' is not one of " + list);
    }
    case ParamType::text:
      if (!std::holds_alternative<std::string>(value)) bad(spec, "must be text, got " + to_string(value));
      return value;
    case ParamType::faces:
    case ParamType::vertices: {
      const auto* ids = std::get_if<Ids>(&value);
      if (!ids)
        bad(spec, "must be a list of " + std::string(spec.type == ParamType::faces ? "face" : "vertex") + " ids, got " +
                      to_string(value));
      Ids sorted = *ids;
      std::sort(sorted.begin(), sorted.end());
      sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
      return sorted;
    }
  }
  return value;
}

void detail::check_described(const std::vector<ParamSpec>& specs, const Mesh* mesh) {
  std::map<std::string, ParamValue> selections;
  for (const ParamSpec& s : specs) {
    check_param(s, s.default_value);
    if (is_selection(s.type)) selections[s.name] = s.default_value;
  }
  if (mesh) check_selections(specs, selections, mesh->num_vertices(), mesh->num_faces());
}

std::size_t detail::enum_index(const ParamInfo& i, const std::string& choice) {
  const auto it = std::find(i.choices.begin(), i.choices.end(), choice);
  if (it == i.choices.end()) throw InvalidInput("'" + choice + "' is not a choice");  // check_param said so first
  return std::size_t(it - i.choices.begin());
}

ParamValue parse_param(const ParamSpec& spec, const std::string& text) {
  switch (spec.type) {
    case ParamType::integer: {
      long long n = 0;
      const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), n);
      if (ec != std::errc() || p != text.data() + text.size()) bad(spec, "must be an integer, got '" + text + "'");
      return check_param(spec, n);
    }
    case ParamType::number: {
      double d = 0;
      const auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), d);
      if (ec != std::errc() || p != text.data() + text.size()) bad(spec, "must be a number, got '" + text + "'");
      return check_param(spec, d);
    }
    case ParamType::boolean:
      if (text == "true" || text == "1" || text == "yes" || text == "on") return true;
      if (text == "false" || text == "0" || text == "no" || text == "off") return false;
      bad(spec, "must be true or false, got '" + text + "'");
    case ParamType::choice:
    case ParamType::text:
      return check_param(spec, text);
    case ParamType::faces:
    case ParamType::vertices: {
      Ids ids;
      const char* p = text.data();
      const char* const end = p + text.size();
      while (p < end) {
        if (*p == ',' || std::isspace((unsigned char)*p)) {
          ++p;
          continue;
        }
        unsigned long long n = 0;
        const auto [q, ec] = std::from_chars(p, end, n);
        if (ec != std::errc() || n > 0xffffffffULL || (q < end && *q != ',' && !std::isspace((unsigned char)*q)))
          bad(spec, "must be ids separated by commas, got '" + text.substr(std::size_t(p - text.data()), 20) + "'");
        ids.push_back(Index(n));
        p = q;
      }
      return check_param(spec, ids);
    }
  }
  return text;
}

namespace detail {

void SpecCollector::add(const char* n, ParamType t, ParamValue v, ParamInfo i) {
  if (i.label.empty()) i.label = n;
  specs.push_back({n, t, std::move(v), std::move(i)});
}

namespace {
// The checked value of n, when the job gives one.
std::optional<ParamValue> checked(const ValueAssigner& a, const char* n) {
  const auto it = a.values.find(n);
  if (it == a.values.end()) return std::nullopt;
  return check_param(a.spec(n), it->second);
}
}  // namespace

void ValueAssigner::set(const char* n, long long& f) {
  if (auto v = checked(*this, n)) f = std::get<long long>(*v);
}
void ValueAssigner::set(const char* n, int& f) {
  if (auto v = checked(*this, n)) f = int(std::get<long long>(*v));
}
void ValueAssigner::set(const char* n, double& f) {
  if (auto v = checked(*this, n)) f = std::get<double>(*v);
}
void ValueAssigner::set(const char* n, bool& f) {
  if (auto v = checked(*this, n)) f = std::get<bool>(*v);
}
void ValueAssigner::set(const char* n, std::string& f) {
  if (auto v = checked(*this, n)) f = std::move(std::get<std::string>(*v));
}
void ValueAssigner::set(const char* n, Ids& f) {
  if (auto v = checked(*this, n)) f = std::move(std::get<Ids>(*v));
}

Algorithm assemble(const char* name, AlgorithmInfo info, const TypedAlgorithm& typed) {
  info.name = name;
  if (info.outputs.empty() && typed.outputs) typed.outputs(info.outputs);
  SpecCollector collect;
  typed.collect(collect);
  Algorithm a;
  a.info = std::move(info);
  a.params = collect.specs;
  a.run = [run = typed.run, specs = std::move(collect.specs), algo = a.info.name](
              const Inputs& in, const std::map<std::string, ParamValue>& values, Context& ctx) {
    check_names(algo, values, specs);
    if (in.has("mesh")) check_selections(specs, values, in.mesh().num_vertices(), in.mesh().num_faces());
    ValueAssigner assign{values, specs};
    return run(in, assign, ctx);
  };
  return a;
}

Registrar::Registrar(Algorithm a) { register_algorithm(std::move(a)); }
Registrar::Registrar(const char* name, const AlgorithmInfo& info, const TypedAlgorithm& typed) {
  register_algorithm(assemble(name, info, typed));
}

void set_typed_precheck(const char* name, void (*collect)(SpecCollector&),
                        void (*check)(const InputSummaries&, ValueAssigner&)) {
  SpecCollector c;
  collect(c);
  set_precheck(name, [check, specs = std::move(c.specs)](const InputSummaries& in,
                                                         const std::map<std::string, ParamValue>& values) {
    ValueAssigner assign{values, specs};
    check(in, assign);
  });
}

void add_output(std::vector<std::pair<std::string, OutputKind>>& outputs, const char* name, OutputKind kind) {
  outputs.emplace_back(name, kind);
}
void add_artifact(AlgorithmResult& out, const char* name, Mesh&& v) { out.artifacts.push_back({name, std::move(v)}); }
void add_artifact(AlgorithmResult& out, const char* name, ScalarField&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, VoxelGrid&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, Skeleton&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, Metrics&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, Text&& v) { out.artifacts.push_back({name, std::move(v)}); }
void add_artifact(AlgorithmResult& out, const char* name, Animation&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, VectorField&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_artifact(AlgorithmResult& out, const char* name, PointCloud&& v) {
  out.artifacts.push_back({name, std::move(v)});
}
void add_warnings(AlgorithmResult& out, std::vector<std::string>&& warnings) { out.warnings = std::move(warnings); }

const ParamSpec& ValueAssigner::spec(const char* n) const {
  for (const auto& s : specs)
    if (s.name == n) return s;
  throw std::logic_error(std::string("no spec for parameter ") + n);
}

void check_names(const std::string& algorithm, const std::map<std::string, ParamValue>& values,
                 const std::vector<ParamSpec>& specs) {
  for (const auto& [name, v] : values) {
    bool known = false;
    for (const auto& s : specs) known |= s.name == name;
    if (!known) {
      std::string list;
      for (const auto& s : specs) list += (list.empty() ? "" : ", ") + s.name;
      throw InvalidInput("algorithm '" + algorithm + "' has no parameter '" + name + "'" +
                         (list.empty() ? " (it takes none)" : " (it takes: " + list + ")"));
    }
  }
}

}  // namespace detail
}  // namespace cgview
