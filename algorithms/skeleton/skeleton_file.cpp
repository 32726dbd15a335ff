// skeleton_file: a skeleton made by another tool, attached to a mesh: the
// file's text (CGAL's polylines, .cg, OBJ with l records, JSON) is the
// parameter, the skeleton and its measures against the mesh the outputs.
// Uploading a skeleton is running this algorithm, so that an uploaded
// skeleton is an artifact like any made by a job: drawn, compared, measured,
// an input of the next job, owned and shared as jobs are.  A malformed file
// is refused at submission (the precheck parses it), naming its line.
#include "io/skeleton_io.h"
#include "registry/registry.h"
#include "skeleton/skeleton_metrics.h"

namespace cgview {
namespace {

struct Params {
  std::string name = "skeleton.cg";
  std::string text;
  template <class V>
  void describe(V& v) {
    v.text("name", name,
           {.label = "File name", .help = "its extension names the format: .polylines.txt, .cg, .obj or .json"});
    v.text("text", text, {.label = "File contents", .help = "the skeleton file's text"});
  }
};

Skeleton parse(const Params& p) {
  if (p.text.empty()) throw InvalidInput("parameter 'text': the skeleton file is empty");
  return read_skeleton_bytes(p.text, skeleton_format_from_name(p.name), p.name);
}

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  Skeleton s = parse(p);
  ctx.progress(0.5, "measuring");
  Metrics m = metrics_table(skeleton_metrics(s, mesh));
  ctx.progress(1.0, "done");
  return {{{"skeleton", std::move(s)}, {"metrics", std::move(m)}}, {}};
}

void precheck(const InputSummaries&, const Params& p) { parse(p); }

CGVIEW_REGISTER_ALGORITHM(
    skeleton_file, Params, run,
    {.title = "Skeleton from a file",
     .description = "Attaches a skeleton made by another tool (CGAL polylines, .cg, OBJ l records, "
                    "JSON) to the mesh, with its measures against it.",
     .area = "skeleton",
     .outputs = {{"skeleton", OutputKind::skeleton}, {"metrics", OutputKind::metrics}}});
CGVIEW_REGISTER_PRECHECK(skeleton_file, Params, precheck)

}  // namespace
}  // namespace cgview
