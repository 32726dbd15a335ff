// Not CGAL's sample_triangle_mesh: in CGAL 5.5 its random_seed only picks the
// triangles, and the point inside each one comes from the global
// get_default_random() (Generic_random_point_generator), so the same seed
// gives different points and concurrent jobs share one generator.  Sampling
// by area is a prefix sum and two uniforms (Turk 1990), with std::mt19937_64.
#include "filters/sample_points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

namespace cgview {

SamplePointsResult sample_points(const Mesh& mesh, const SamplePointsParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("sample_points needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  ctx.progress(0.0, "areas");
  std::vector<double> cumulative = face_areas(mesh);
  for (std::size_t f = 1; f < cumulative.size(); ++f) cumulative[f] += cumulative[f - 1];
  const double total = cumulative.back();
  if (!(total > 0) || !std::isfinite(total))
    throw InvalidInput("sample_points needs a surface with area: every face is degenerate");

  std::mt19937_64 rng(static_cast<std::uint64_t>(p.seed));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Mesh out;
  out.positions.reserve(std::size_t(p.count));
  for (int i = 0; i < p.count; ++i) {
    if (i % 65536 == 0) {
      ctx.check_cancelled();
      ctx.progress(0.05 + 0.95 * i / p.count, "sampling");
    }
    const double pick = uniform(rng) * total;
    const std::size_t f =
        std::min(std::size_t(std::upper_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin()),
                 cumulative.size() - 1);
    // sqrt makes the barycentric coordinates uniform over the triangle's area.
    const double s = std::sqrt(uniform(rng)), t = uniform(rng);
    const Tri& tri = mesh.faces[f];
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    out.positions.push_back(a * (1 - s) + b * (s * (1 - t)) + c * (s * t));
  }
  SamplePointsResult result;
  result.points = std::move(out);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(sample_points, sample_points,
                         {.title = "Sample points",
                          .description = "Points drawn uniformly by area over the surface, reproducible by seed: a "
                                         "point cloud, a mesh with no faces (written as .ply).",
                          .area = "filters"})

}  // namespace cgview
