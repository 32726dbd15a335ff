// The algorithm registry: every algorithm described once (name, title,
// parameters with their types, defaults, ranges and help, outputs), so that
// the REST API, `cgview run` and the viewer's forms are generated from it.
//
// An algorithm is a function that a program calls directly, declared in its
// header and registered at the end of its .cpp (the template:
// algorithms/examples/centroid_distance.{h,cpp}; a choice as an enum:
// algorithms/filters/smooth.h):
//
//   struct ScaleParams {
//     double factor = 1.0;                               // the default, once
//     template <class V> void describe(V& v) {
//       v.number("factor", factor, {.label = "Factor", .min = 0, .max = 10, .help = "..."});
//     }
//   };
//   struct ScaleResult {
//     Mesh mesh;                                         // one member per output
//     std::vector<std::string> warnings;
//     template <class V> void outputs(V& v) { v("mesh", mesh); }
//   };
//   ScaleResult scale(const Mesh& mesh, const ScaleParams& p = {}, Context* ctx = nullptr);
//
//   // scale.cpp: the function starts with check_params(p) and reports
//   // through context_or_none(ctx); then
//   CGVIEW_REGISTER_FUNCTION(scale, scale, {.title = "...", .description = "...", .area = "..."})
//
// Its parameters come from describe, its outputs from outputs().  An
// algorithm of several inputs (hausdorff: "mesh" and "reference") lists them
// in `.inputs`, takes them as arguments, and registers a lambda of
// (const Inputs&, const ScaleParams&, Context*) that picks them by name.
//
// CGVIEW_REGISTER_ALGORITHM(name, Params, run, {...}), around an
// AlgorithmResult run(const Mesh&, const Params&, Context&) that lists its
// outputs itself (and in `.outputs`), remains for plugins written with it
// and for hand-written adapters (server/plugin_build_algorithm.cpp).
//
// The visitor pattern keeps each parameter's label, range and help beside
// its field and its default in the field's initializer, and nowhere else.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "core/animation.h"
#include "core/errors.h"
#include "core/mesh.h"
#include "core/point_cloud.h"
#include "core/scalar_field.h"
#include "core/skeleton.h"
#include "core/vector_field.h"
#include "core/voxel_grid.h"

namespace cgview {

// A job was cancelled: thrown by Context::check_cancelled().
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

// faces / vertices: a selection, a set of ids of the first input mesh's
// faces or vertices (what the viewer's selection tool sends), sorted and
// unique once checked; empty by default.  Ids out of range are refused
// (check_selections) before the algorithm runs.
enum class ParamType { integer, number, boolean, choice, text, faces, vertices };
using Ids = std::vector<Index>;
using ParamValue = std::variant<long long, double, bool, std::string, Ids>;

// A parameter that applies only while another one, a choice or a boolean,
// has one of some values ({"map", {"ikeda", "composite"}}; a boolean's
// values are "true" and "false"): forms show it only then.  Empty: always.
struct ParamCondition {
  std::string param{};
  std::vector<std::string> values{};
};

// Every member has an initializer so that a designated initializer naming
// only some ({.label = ..., .help = ...}) draws no -Wmissing-field-initializers.
// Forms list the parameters in their declared order: the most used first.
struct ParamInfo {
  std::string label{};  // for forms; defaults to the name
  std::optional<double> min{}, max{};
  std::string help{};
  std::vector<std::string> choices{};  // for choice parameters
  bool advanced{};                     // forms fold it under "Advanced": render contexts, internal limits
  ParamCondition when{};
};

struct ParamSpec {
  std::string name;
  ParamType type = ParamType::number;
  ParamValue default_value;
  ParamInfo info;
};

// One result of an algorithm, named ("sdf", "skeleton", "metrics").
using Metrics = std::map<std::string, double>;
// Bytes for the user, kept as they are (a message extracted by chaos_extract):
// saved as .txt or .bin.
struct Text {
  std::string bytes;
};
struct Artifact {
  std::string name;
  std::variant<Mesh, ScalarField, VoxelGrid, Skeleton, Metrics, Text, Animation, VectorField, PointCloud> value;
};

struct AlgorithmResult {
  std::vector<Artifact> artifacts;
  std::vector<std::string> warnings;
};

// What a running algorithm may ask: report progress, check for cancellation.
class Context {
 public:
  using ProgressFn = std::function<void(double fraction, std::string_view stage)>;
  Context() = default;
  Context(ProgressFn progress, std::function<bool()> cancelled)
      : progress_(std::move(progress)), cancelled_(std::move(cancelled)) {}
  // fraction in [0, 1] of the whole run; stage names the current step.
  void progress(double fraction, std::string_view stage) const {
    if (progress_) progress_(fraction, stage);
  }
  bool cancelled() const { return cancelled_ && cancelled_(); }
  // Throws Cancelled when the job was cancelled; call it in long loops.
  void check_cancelled() const {
    if (cancelled()) throw Cancelled();
  }

 private:
  ProgressFn progress_;
  std::function<bool()> cancelled_;
};

// The kinds of output an algorithm declares.
// points: a PointCloud (core/point_cloud.h), named "points".
enum class OutputKind { mesh, scalar_field, voxel_grid, skeleton, metrics, text, animation, vector_field, points };
// Every kind, in the order lists show them.
inline constexpr OutputKind kOutputKinds[] = {
    OutputKind::mesh,         OutputKind::points,     OutputKind::scalar_field,
    OutputKind::vector_field, OutputKind::voxel_grid, OutputKind::skeleton,
    OutputKind::metrics,      OutputKind::text,       OutputKind::animation};

// An algorithm's named input ("mesh", "reference", "grid"), of one kind.
struct InputSpec {  // initializers as in ParamInfo
  std::string name{};
  OutputKind kind = OutputKind::mesh;
  std::string help{};
  // The algorithm needs the mesh's inside (rays cast along the inward
  // normal): a closed mesh whose faces face inward is turned outward for
  // the run (face indices kept), and a warning says so.
  bool outward = false;
  // A mesh input that may be a mesh with no faces, a point cloud
  // (voxelize's surface mode); without it the server refuses a cloud with a
  // 400 before the job runs, and `cgview run` and the worker before reading on.
  bool faceless = false;
};

// The inputs of one run, by name; it refers to values the caller owns.
// A Mesh converts to {"mesh": mesh}, the input of most algorithms.
class Inputs {
 public:
  Inputs() = default;
  Inputs(const Mesh& mesh) { add("mesh", mesh); }  // NOLINT: implicit on purpose
  void add(const std::string& name, const Mesh& v) { values_[name] = &v; }
  void add(const std::string& name, const ScalarField& v) { values_[name] = &v; }
  void add(const std::string& name, const VoxelGrid& v) { values_[name] = &v; }
  void add(const std::string& name, const Skeleton& v) { values_[name] = &v; }
  void add(const std::string& name, const PointCloud& v) { values_[name] = &v; }
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  // The input of that name; throws InvalidInput when it is missing or of
  // another kind ("input 'reference' is missing").
  const Mesh& mesh(const std::string& name = "mesh") const { return get<Mesh>(name, "a mesh"); }
  const ScalarField& scalar_field(const std::string& name) const { return get<ScalarField>(name, "a scalar field"); }
  const VoxelGrid& voxel_grid(const std::string& name) const { return get<VoxelGrid>(name, "a voxel grid"); }
  const Skeleton& skeleton(const std::string& name) const { return get<Skeleton>(name, "a skeleton"); }
  const PointCloud& points(const std::string& name) const { return get<PointCloud>(name, "a point cloud"); }

 private:
  template <class T>
  const T& get(const std::string& name, const char* what) const {
    const auto it = values_.find(name);
    if (it == values_.end()) throw InvalidInput("input '" + name + "' is missing");
    const auto* const* v = std::get_if<const T*>(&it->second);
    if (!v) throw InvalidInput("input '" + name + "' must be " + std::string(what));
    return **v;
  }
  std::map<std::string,
           std::variant<const Mesh*, const ScalarField*, const VoxelGrid*, const Skeleton*, const PointCloud*>>
      values_;
};

struct AlgorithmInfo {  // initializers as in ParamInfo
  std::string name{};   // snake_case, unique
  std::string title{};
  std::string description{};
  std::string area{};  // "examples", "sdf", ...
  std::vector<std::pair<std::string, OutputKind>> outputs{};
  // What it takes; the default is one mesh named "mesh".
  std::vector<InputSpec> inputs{{.name = "mesh", .kind = OutputKind::mesh, .help = "the mesh to process"}};
};

// What is known of a mesh input before a job runs (the server has its stored
// report): enough for a precheck to refuse parameters that cannot fit it.
struct InputSummary {
  BBox bbox;
  std::size_t vertices = 0, faces = 0;
};
using InputSummaries = std::map<std::string, InputSummary>;

struct Algorithm {
  AlgorithmInfo info;
  std::vector<ParamSpec> params;
  // Optional, cheap: throws InvalidInput for parameters the inputs cannot
  // take (voxelize: a grid over its memory limit), so that the server answers
  // 400 at submission instead of failing the job later.  Set by
  // CGVIEW_REGISTER_PRECHECK.
  std::function<void(const InputSummaries&, const std::map<std::string, ParamValue>&)> precheck;
  // Checks and converts the values (missing ones take their defaults), then
  // runs.  Throws InvalidInput naming the bad parameter and the rule broken.
  // Inputs missing from `inputs` throw InvalidInput naming them.
  std::function<AlgorithmResult(const Inputs&, const std::map<std::string, ParamValue>&, Context&)> run;
};

// Every registered algorithm, by name.
const std::map<std::string, Algorithm>& algorithms();
// The algorithm of that name; throws std::out_of_range naming it.
const Algorithm& find_algorithm(const std::string& name);
void register_algorithm(Algorithm algorithm);
// Throws InvalidInput unless every parameter's `when` names another
// parameter of the list, a choice or a boolean, and values it can take.
void check_conditions(const std::vector<ParamSpec>& specs);

// Converts text (a CLI argument) to a parameter's type; throws InvalidInput.
// A selection is a list of ids separated by commas or white space ("1,2,3").
ParamValue parse_param(const ParamSpec& spec, const std::string& text);
// Checks a value against its spec (type, range, choices); returns it
// normalized (an integer given for a number becomes a double); throws
// InvalidInput "parameter 'rays': 500 is over the maximum 100".
ParamValue check_param(const ParamSpec& spec, const ParamValue& value);
std::string to_string(const ParamValue& v);
const char* to_string(ParamType t);
const char* to_string(OutputKind k);
bool is_selection(ParamType t);
// Throws InvalidInput naming the first selection id (a faces or vertices
// parameter) out of range for a mesh of that many vertices and faces:
// "parameter 'faces': face id 12 is out of range (the mesh has 12 faces)".
void check_selections(const std::vector<ParamSpec>& specs, const std::map<std::string, ParamValue>& values,
                      std::size_t vertices, std::size_t faces);

namespace detail {

// A choice held as an enum: its values are the choices, in order (the
// first choice is the enum's 0).  Throws InvalidInput for a value past them.
template <class E>
std::string enum_name(const char* param, E v, const ParamInfo& i) {
  const auto k = static_cast<std::size_t>(v);
  if (k >= i.choices.size())
    throw InvalidInput("parameter '" + std::string(param) + "': " + std::to_string(k) + " is not one of its " +
                       std::to_string(i.choices.size()) + " choices");
  return i.choices[k];
}
std::size_t enum_index(const ParamInfo& i, const std::string& choice);

// Collects the specs of a Params struct (defaults from a default instance).
struct SpecCollector {
  std::vector<ParamSpec> specs;
  void integer(const char* n, long long& v, ParamInfo i = {}) { add(n, ParamType::integer, v, i); }
  void integer(const char* n, int& v, ParamInfo i = {}) { add(n, ParamType::integer, (long long)v, i); }
  void number(const char* n, double& v, ParamInfo i = {}) { add(n, ParamType::number, v, i); }
  void boolean(const char* n, bool& v, ParamInfo i = {}) { add(n, ParamType::boolean, v, i); }
  void choice(const char* n, std::string& v, ParamInfo i) { add(n, ParamType::choice, v, i); }
  template <class E>
  requires std::is_enum_v<E>
  void choice(const char* n, E& v, ParamInfo i) { add(n, ParamType::choice, enum_name(n, v, i), i); }
  void text(const char* n, std::string& v, ParamInfo i = {}) { add(n, ParamType::text, v, i); }
  void faces(const char* n, Ids& v, ParamInfo i = {}) { add(n, ParamType::faces, v, i); }
  void vertices(const char* n, Ids& v, ParamInfo i = {}) { add(n, ParamType::vertices, v, i); }
  void add(const char* n, ParamType t, ParamValue v, ParamInfo i);
};

// Assigns checked values to a Params struct's fields.
struct ValueAssigner {
  const std::map<std::string, ParamValue>& values;
  const std::vector<ParamSpec>& specs;
  const ParamSpec& spec(const char* n) const;
  // The checked value of n into its field, when given (in the library, so
  // that an algorithm's file does not compile them).
  void set(const char* n, long long& field);
  void set(const char* n, int& field);
  void set(const char* n, double& field);
  void set(const char* n, bool& field);
  void set(const char* n, std::string& field);
  void set(const char* n, Ids& field);
  void integer(const char* n, long long& v, const ParamInfo& = {}) { set(n, v); }
  void integer(const char* n, int& v, const ParamInfo& = {}) { set(n, v); }
  void number(const char* n, double& v, const ParamInfo& = {}) { set(n, v); }
  void boolean(const char* n, bool& v, const ParamInfo& = {}) { set(n, v); }
  void choice(const char* n, std::string& v, const ParamInfo&) { set(n, v); }
  template <class E>
  requires std::is_enum_v<E>
  void choice(const char* n, E& v, const ParamInfo& i) {
    std::string name;
    set(n, name);
    if (!name.empty()) v = E(enum_index(i, name));
  }
  void text(const char* n, std::string& v, const ParamInfo& = {}) { set(n, v); }
  void faces(const char* n, Ids& v, const ParamInfo& = {}) { set(n, v); }
  void vertices(const char* n, Ids& v, const ParamInfo& = {}) { set(n, v); }
};

// While a plugin loads (plugins/plugin.h): an algorithm whose name is taken
// is not registered and its name goes to `sink`, instead of a throw that
// could not leave the library's initialisation.  nullptr: throw again.
void set_registration_clashes(std::vector<std::string>* sink);

void check_names(const std::string& algorithm, const std::map<std::string, ParamValue>& values,
                 const std::vector<ParamSpec>& specs);

// An algorithm's typed part, as plain functions of its Params and result
// types; the rest (specs, checks, the std::function, the registry entry) is
// done once, in the library (registry.cpp).  A plugin, compiled at every Run
// and at every graded submission, then compiles these few lines and not the
// registry's machinery: about 0.3 s instead of 1.5 s for a small one.
struct TypedAlgorithm {
  void (*collect)(SpecCollector&);                                    // the specs of a default Params
  void (*outputs)(std::vector<std::pair<std::string, OutputKind>>&);  // its result's, or nullptr
  AlgorithmResult (*run)(const Inputs&, ValueAssigner&, Context&);    // assigns the values, runs
};
Algorithm assemble(const char* name, AlgorithmInfo info, const TypedAlgorithm& typed);
void register_typed(const char* name, const AlgorithmInfo& info, const TypedAlgorithm& typed);
// Gives a registered algorithm its precheck: check(summaries, assigner).
void set_typed_precheck(const char* name, void (*collect)(SpecCollector&),
                        void (*check)(const InputSummaries&, ValueAssigner&));

template <class Params>
void collect_defaults(SpecCollector& c) {
  Params defaults;
  defaults.describe(c);
}

// Algorithms of several inputs take them all by name; the others take the
// mesh (tested in this order: a Mesh converts to Inputs, not back).
template <class Params, auto Fn>
AlgorithmResult run_algorithm(const Inputs& in, ValueAssigner& assign, Context& ctx) {
  Params p;
  p.describe(assign);
  if constexpr (std::is_invocable_v<decltype(Fn), const Inputs&, const Params&, Context&>) return Fn(in, p, ctx);
  else return Fn(in.mesh("mesh"), p, ctx);
}

template <class Params, auto Fn>
Algorithm make_algorithm(const char* name, AlgorithmInfo info) {
  return assemble(name, std::move(info), {&collect_defaults<Params>, nullptr, &run_algorithm<Params, Fn>});
}

template <class Params, auto Fn>
void check_typed(const InputSummaries& in, ValueAssigner& assign) {
  Params p;
  p.describe(assign);
  Fn(in, p);
}

struct Registrar {
  explicit Registrar(Algorithm a);
  Registrar(const char* name, const AlgorithmInfo& info, const TypedAlgorithm& typed);
};

// Gives a registered algorithm its precheck, fn(const InputSummaries&, const Params&).
void set_precheck(const std::string& name,
                  std::function<void(const InputSummaries&, const std::map<std::string, ParamValue>&)> check);
template <class Params, auto Fn>
struct PrecheckRegistrar {
  explicit PrecheckRegistrar(const char* name) {
    set_typed_precheck(name, &collect_defaults<Params>, &check_typed<Params, Fn>);
  }
};

// An algorithm written as a function (see algorithms/filters/smooth.h):
//   NameResult name(const Mesh&, const NameParams& = {}, Context* = nullptr);
// or, for several inputs, a function of (const Inputs&, const NameParams&,
// Context*) that picks them by name.  Its result struct lists its artifacts
// with `template <class V> void outputs(V& v) { v("mesh", mesh); ... }` (a
// std::optional one is left out while empty) and has `warnings`.
template <class F>
struct FunctionTraits : FunctionTraits<decltype(&F::operator())> {};
template <class R, class In, class P>
struct FunctionTraits<R (*)(In, const P&, Context*)> {
  using Result = R;
  using Params = P;
};
template <class C, class R, class In, class P>
struct FunctionTraits<R (C::*)(In, const P&, Context*) const> {
  using Result = R;
  using Params = P;
};

template <class T>
struct ArtifactKind;
template <>
struct ArtifactKind<Mesh> : std::integral_constant<OutputKind, OutputKind::mesh> {};
template <>
struct ArtifactKind<ScalarField> : std::integral_constant<OutputKind, OutputKind::scalar_field> {};
template <>
struct ArtifactKind<VoxelGrid> : std::integral_constant<OutputKind, OutputKind::voxel_grid> {};
template <>
struct ArtifactKind<Skeleton> : std::integral_constant<OutputKind, OutputKind::skeleton> {};
template <>
struct ArtifactKind<Metrics> : std::integral_constant<OutputKind, OutputKind::metrics> {};
template <>
struct ArtifactKind<Text> : std::integral_constant<OutputKind, OutputKind::text> {};
template <>
struct ArtifactKind<Animation> : std::integral_constant<OutputKind, OutputKind::animation> {};
template <>
struct ArtifactKind<VectorField> : std::integral_constant<OutputKind, OutputKind::vector_field> {};
template <>
struct ArtifactKind<PointCloud> : std::integral_constant<OutputKind, OutputKind::points> {};
template <class T>
struct ArtifactKind<std::optional<T>> : ArtifactKind<T> {};

void add_output(std::vector<std::pair<std::string, OutputKind>>& outputs, const char* name, OutputKind kind);
// Moves a result struct's artifacts into an AlgorithmResult (one overload
// per kind, in the library).
void add_artifact(AlgorithmResult& out, const char* name, Mesh&& v);
void add_artifact(AlgorithmResult& out, const char* name, ScalarField&& v);
void add_artifact(AlgorithmResult& out, const char* name, VoxelGrid&& v);
void add_artifact(AlgorithmResult& out, const char* name, Skeleton&& v);
void add_artifact(AlgorithmResult& out, const char* name, Metrics&& v);
void add_artifact(AlgorithmResult& out, const char* name, Text&& v);
void add_artifact(AlgorithmResult& out, const char* name, Animation&& v);
void add_artifact(AlgorithmResult& out, const char* name, VectorField&& v);
void add_artifact(AlgorithmResult& out, const char* name, PointCloud&& v);
void add_warnings(AlgorithmResult& out, std::vector<std::string>&& warnings);
// Names the outputs a result struct declares, with their kinds.
struct OutputCollector {
  std::vector<std::pair<std::string, OutputKind>>& outputs;
  template <class T>
  void operator()(const char* name, T&) {
    add_output(outputs, name, ArtifactKind<T>::value);
  }
};
struct ArtifactMover {
  AlgorithmResult& out;
  template <class T>
  void operator()(const char* name, T& v) {
    add_artifact(out, name, std::move(v));
  }
  template <class T>
  void operator()(const char* name, std::optional<T>& v) {
    if (v) add_artifact(out, name, std::move(*v));
  }
};

template <class Result>
void collect_outputs(std::vector<std::pair<std::string, OutputKind>>& outputs) {
  Result r;
  OutputCollector c{outputs};
  r.outputs(c);
}

template <auto Fn>
AlgorithmResult run_function(const Inputs& in, ValueAssigner& assign, Context& ctx) {
  using Params = typename FunctionTraits<decltype(Fn)>::Params;
  using Result = typename FunctionTraits<decltype(Fn)>::Result;
  Params p;
  p.describe(assign);
  Result r = [&] {
    if constexpr (std::is_invocable_v<decltype(Fn), const Inputs&, const Params&, Context*>) return Fn(in, p, &ctx);
    else return Fn(in.mesh("mesh"), p, &ctx);
  }();
  AlgorithmResult out;
  ArtifactMover move{out};
  r.outputs(move);
  add_warnings(out, std::move(r.warnings));
  return out;
}

template <auto Fn>
constexpr TypedAlgorithm typed_function() {
  using Traits = FunctionTraits<decltype(Fn)>;
  return {&collect_defaults<typename Traits::Params>, &collect_outputs<typename Traits::Result>, &run_function<Fn>};
}

template <auto Fn>
Algorithm make_function_algorithm(const char* name, AlgorithmInfo info) {
  return assemble(name, std::move(info), typed_function<Fn>());
}

}  // namespace detail

namespace detail {
// Checks each spec's default (here: the values of a Params struct, collected
// by SpecCollector) as check_param checks a job's value; with a mesh, its
// selections against the mesh too (check_selections).
void check_described(const std::vector<ParamSpec>& specs, const Mesh* mesh);
template <class P>
std::vector<ParamSpec> described(const P& p) {
  P copy = p;  // describe takes its fields by reference
  SpecCollector c;
  copy.describe(c);
  return std::move(c.specs);
}
}  // namespace detail

// Throws InvalidInput naming the first parameter outside its description's
// range or choices: what a function-algorithm checks first, so that a direct
// call is held to the same rules as a job.
template <class P>
void check_params(const P& p) {
  detail::check_described(detail::described(p), nullptr);
}
// The same, and each selection (a faces or vertices parameter) against the
// mesh the ids index, as a job's are.
template <class P>
void check_params(const P& p, const Mesh& mesh) {
  detail::check_described(detail::described(p), &mesh);
}

// The context of a direct call made without one: no progress, never cancelled.
inline const Context& context_or_none(const Context* ctx) {
  static const Context none;
  return ctx ? *ctx : none;
}

}  // namespace cgview

// Registers an algorithm at program start.  NAME: snake_case identifier.
// After CGVIEW_REGISTER_ALGORITHM(NAME, ...) in the same file: a precheck
// FN(const InputSummaries&, const PARAMS&) that throws InvalidInput.
#define CGVIEW_REGISTER_PRECHECK(NAME, PARAMS, FN)                                     \
  namespace {                                                                          \
  const ::cgview::detail::PrecheckRegistrar<PARAMS, FN> cgview_precheck_##NAME{#NAME}; \
  }

// Registers a function-algorithm (make_function_algorithm): NAME, the
// function (a function of the mesh, or of the Inputs for several), and the
// AlgorithmInfo; its outputs come from the result struct.
#define CGVIEW_REGISTER_FUNCTION(NAME, FN, ...)                                                         \
  namespace {                                                                                           \
  const ::cgview::detail::Registrar cgview_registrar_##NAME{#NAME, ::cgview::AlgorithmInfo __VA_ARGS__, \
                                                            ::cgview::detail::typed_function<FN>()};    \
  }

#define CGVIEW_REGISTER_ALGORITHM(NAME, PARAMS, FN, ...)                                                     \
  namespace {                                                                                                \
  const ::cgview::detail::Registrar cgview_registrar_##NAME{                                                 \
      #NAME,                                                                                                 \
      ::cgview::AlgorithmInfo __VA_ARGS__,                                                                   \
      {&::cgview::detail::collect_defaults<PARAMS>, nullptr, &::cgview::detail::run_algorithm<PARAMS, FN>}}; \
  }
