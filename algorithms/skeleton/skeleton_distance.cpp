#include "skeleton/skeleton_distance.h"

#include "skeleton/skeleton_measures.h"

namespace cgview {

SkeletonDistanceResult skeleton_distance(const Skeleton& skeleton, const Skeleton& reference,
                                         const SkeletonDistanceParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0.0, "measuring");
  const SkeletonDistance d = measure_distance(skeleton, reference, p.spacing);
  ctx.progress(1.0, "done");
  SkeletonDistanceResult result;
  result.metrics = Metrics{{"hausdorff", d.hausdorff}, {"mean", d.mean}};
  return result;
}

CGVIEW_REGISTER_FUNCTION(
    skeleton_distance,
    [](const Inputs& in, const SkeletonDistanceParams& p, Context* c) {
      return skeleton_distance(in.skeleton("skeleton"), in.skeleton("reference"), p, c);
    },
    {.title = "Distance between skeletons",
     .description = "Symmetric Hausdorff and mean distance between two skeletons, sampled along their edges.",
     .area = "skeleton",
     .inputs = {{.name = "skeleton", .kind = OutputKind::skeleton, .help = "one skeleton"},
                {.name = "reference", .kind = OutputKind::skeleton, .help = "the skeleton to compare it with"}}})

}  // namespace cgview
