#include "skeleton/skeleton_metrics.h"

namespace cgview {

SkeletonMetricsResult skeleton_metrics(const Mesh& mesh, const Skeleton& skeleton, const SkeletonMetricsParams& p,
                                       Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0.0, "measuring");
  SkeletonMetricsResult result;
  result.metrics = metrics_table(measure_skeleton(skeleton, mesh));
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(
    skeleton_metrics,
    [](const Inputs& in, const SkeletonMetricsParams& p, Context* c) {
      return skeleton_metrics(in.mesh("mesh"), in.skeleton("skeleton"), p, c);
    },
    {.title = "Skeleton metrics",
     .description = "Nodes, branches, endpoints, junctions, loops and length of a skeleton, the "
                    "fraction of its nodes inside the mesh, and how centred it is in the mesh's cross-sections.",
     .area = "skeleton",
     .inputs = {{.name = "mesh", .kind = OutputKind::mesh, .help = "the mesh the skeleton belongs to"},
                {.name = "skeleton", .kind = OutputKind::skeleton, .help = "the skeleton to measure"}}})

}  // namespace cgview
