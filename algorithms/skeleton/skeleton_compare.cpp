// skeleton_metrics and skeleton_distance: the measures of skeleton/
// skeleton_metrics.h as registered algorithms, for the comparison table of
// several skeletons of one mesh (the paper's Figure 5).
#include "registry/registry.h"
#include "skeleton/skeleton_metrics.h"

namespace cgview {
namespace {

struct NoParams {
  template <class V>
  void describe(V&) {}
};

AlgorithmResult run_metrics(const Inputs& in, const NoParams&, Context& ctx) {
  ctx.progress(0.0, "measuring");
  Metrics m = metrics_table(skeleton_metrics(in.skeleton("skeleton"), in.mesh("mesh")));
  ctx.progress(1.0, "done");
  return {{{"metrics", std::move(m)}}, {}};
}

struct DistanceParams {
  double spacing = 0;
  template <class V>
  void describe(V& v) {
    v.number("spacing", spacing,
             {.label = "Sample spacing",
              .min = 0,
              .help = "distance between samples along the edges (0: 1/500 of the bounding box's diagonal)"});
  }
};

AlgorithmResult run_distance(const Inputs& in, const DistanceParams& p, Context& ctx) {
  ctx.progress(0.0, "measuring");
  const SkeletonDistance d = skeleton_distance(in.skeleton("skeleton"), in.skeleton("reference"), p.spacing);
  ctx.progress(1.0, "done");
  return {{{"metrics", Metrics{{"hausdorff", d.hausdorff}, {"mean", d.mean}}}}, {}};
}

CGVIEW_REGISTER_ALGORITHM(
    skeleton_metrics, NoParams, run_metrics,
    {.title = "Skeleton metrics",
     .description = "Nodes, branches, endpoints, junctions, loops and length of a skeleton, the "
                    "fraction of its nodes inside the mesh, and how centred it is in the mesh's cross-sections.",
     .area = "skeleton",
     .outputs = {{"metrics", OutputKind::metrics}},
     .inputs = {{.name = "mesh", .kind = OutputKind::mesh, .help = "the mesh the skeleton belongs to"},
                {.name = "skeleton", .kind = OutputKind::skeleton, .help = "the skeleton to measure"}}});

CGVIEW_REGISTER_ALGORITHM(
    skeleton_distance, DistanceParams, run_distance,
    {.title = "Distance between skeletons",
     .description = "Symmetric Hausdorff and mean distance between two skeletons, sampled along their edges.",
     .area = "skeleton",
     .outputs = {{"metrics", OutputKind::metrics}},
     .inputs = {{.name = "skeleton", .kind = OutputKind::skeleton, .help = "one skeleton"},
                {.name = "reference", .kind = OutputKind::skeleton, .help = "the skeleton to compare it with"}}});

}  // namespace
}  // namespace cgview
