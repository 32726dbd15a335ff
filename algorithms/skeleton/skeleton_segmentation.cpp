#include "skeleton/skeleton_segmentation.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "rays/ray_caster.h"

namespace cgview {

SkeletonSegmentationResult skeleton_segmentation(const Mesh& mesh, const Skeleton& s,
                                                 const SkeletonSegmentationParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  s.validate();
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces");
  const std::vector<std::vector<Index>> branches = skeleton_branches(s);
  if (branches.empty()) throw InvalidInput("the skeleton has no edge: there is no branch to assign faces to");
  const RayCaster caster(mesh);
  SkeletonSegmentationResult result;
  ScalarField& field = result.branch;
  field = ScalarField{"branch", Location::face, ColorHint::categorical, std::vector<float>(mesh.faces.size())};
  std::vector<std::pair<double, Vec3>> best(branches.size());
  std::vector<std::size_t> order(branches.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (f % 4096 == 0) {
      ctx.check_cancelled();
      ctx.progress(double(f) / double(mesh.faces.size()), "assigning faces");
    }
    const Vec3 c = face_centroid(mesh, f);
    for (std::size_t b = 0; b < branches.size(); ++b) {
      best[b] = {HUGE_VAL, {}};
      for (std::size_t k = 1; k < branches[b].size(); ++k) {
        const Vec3 q = closest_point_on_segment(c, s.nodes[branches[b][k - 1]], s.nodes[branches[b][k]]);
        const double d = norm(q - c);
        if (d < best[b].first) best[b] = {d, q};
      }
    }
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return best[a].first < best[b].first; });
    std::size_t chosen = order[0];
    for (std::size_t b : order) {
      const double d = best[b].first;
      if (!(d > 0) || !caster.first_hit(c, best[b].second - c, std::uint32_t(f), d * (1 - 1e-6))) {
        chosen = b;
        break;
      }
    }
    field.values[f] = float(chosen);
  }
  ctx.progress(1.0, "done");
  result.metrics = Metrics{{"branches", double(branches.size())}};
  return result;
}

CGVIEW_REGISTER_FUNCTION(
    skeleton_segmentation,
    [](const Inputs& in, const SkeletonSegmentationParams& p, Context* c) {
      return skeleton_segmentation(in.mesh("mesh"), in.skeleton("skeleton"), p, c);
    },
    {.title = "Segmentation by skeleton branches",
     .description = "Each face coloured by the nearest skeleton branch it can see (the paper's octopus).",
     .area = "skeleton",
     .inputs = {{.name = "mesh", .kind = OutputKind::mesh, .help = "the mesh to segment"},
                {.name = "skeleton", .kind = OutputKind::skeleton, .help = "its skeleton"}}})

}  // namespace cgview
