// compare_meshes and compare_skeletons: a graded run's output compared with
// the reference's (compare/compare_output.h), as a job of the worker.  A
// mesh or a skeleton is the student's code's output, and measuring its
// distance to the reference costs what its shape makes it cost: in the
// sandbox, under the job's time and memory limits, a hostile shape fails
// its own comparison and holds up nobody's grading.  Linked into the worker
// only; the server hides them ("system") and runs them for grading
// (teaching/grading.h), reading the verdict back as JSON text.
#include <nlohmann/json.hpp>

#include "compare/compare_output.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  std::string spec = "{}";
  template <class V>
  void describe(V& v) {
    v.text("spec", spec,
           {.label = "Comparison", .help = "{\"method\", \"tolerance\", \"keys\"}, as an assignment says"});
  }
};

template <class T>
AlgorithmResult compare(const T& result, const T& reference, const Params& p, Context& ctx) {
  const nlohmann::json spec = nlohmann::json::parse(p.spec, nullptr, false);
  if (spec.is_discarded()) throw InvalidInput("parameter 'spec': not JSON");
  ctx.progress(0.0, "comparing");
  const Verdict v = compare_output(result, reference, compare_spec_from_json(spec, detail::ArtifactKind<T>::value));
  ctx.progress(1.0, "done");
  AlgorithmResult r;
  r.artifacts.push_back(
      {"verdict", Text{nlohmann::json{{"pass", v.pass}, {"reason", v.reason}, {"measures", v.measures}}.dump()}});
  return r;
}

AlgorithmResult meshes(const Inputs& in, const Params& p, Context& ctx) {
  return compare(in.mesh("result"), in.mesh("reference"), p, ctx);
}

AlgorithmResult skeletons(const Inputs& in, const Params& p, Context& ctx) {
  return compare(in.skeleton("result"), in.skeleton("reference"), p, ctx);
}

CGVIEW_REGISTER_ALGORITHM(compare_meshes, Params, meshes,
                          {.title = "Compare a mesh with its reference",
                           .description = "A graded run's mesh against the reference's (the server's).",
                           .area = "system",
                           .outputs = {{"verdict", OutputKind::text}},
                           .inputs = {{.name = "result", .kind = OutputKind::mesh, .help = "the run's mesh"},
                                      {.name = "reference", .kind = OutputKind::mesh, .help = "the reference's"}}})

CGVIEW_REGISTER_ALGORITHM(compare_skeletons, Params, skeletons,
                          {.title = "Compare a skeleton with its reference",
                           .description = "A graded run's skeleton against the reference's (the server's).",
                           .area = "system",
                           .outputs = {{"verdict", OutputKind::text}},
                           .inputs = {{.name = "result", .kind = OutputKind::skeleton, .help = "the run's skeleton"},
                                      {.name = "reference", .kind = OutputKind::skeleton, .help = "the reference's"}}})

}  // namespace
}  // namespace cgview
