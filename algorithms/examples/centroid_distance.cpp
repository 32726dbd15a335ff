#include "examples/centroid_distance.h"

#include <algorithm>
#include <cmath>

namespace cgview {

CentroidDistanceResult centroid_distance(const Mesh& mesh, const CentroidDistanceParams& p, Context* context) {
  check_params(p);  // the ranges of describe, as a job's values are checked
  const Context& ctx = context_or_none(context);
  if (mesh.num_vertices() == 0) throw InvalidInput("the mesh has no vertices");
  Vec3 c{};
  for (const Vec3& v : mesh.positions) c += v;
  c = c / double(mesh.num_vertices());
  ScalarField field{"centroid_distance", Location::vertex, ColorHint::magnitude, {}};
  field.values.resize(mesh.num_vertices());
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (i % 65536 == 0) {
      ctx.check_cancelled();
      ctx.progress(double(i) / double(mesh.num_vertices()), "distances");
    }
    field.values[i] = float(std::pow(norm(mesh.positions[i] - c), p.exponent));
  }
  if (p.normalize) {
    // As the help says, over the largest distance: a sphere gives all 1, not
    // the min-max stretch of ScalarField::normalized().
    const float largest = *std::max_element(field.values.begin(), field.values.end());
    if (largest > 0)
      for (float& v : field.values) v /= largest;
  }
  ctx.progress(1.0, "done");
  return {.distance = std::move(field), .warnings = {}};
}

CGVIEW_REGISTER_FUNCTION(centroid_distance, centroid_distance,
                         {.title = "Distance from the centroid",
                          .description = "Per-vertex distance from the mesh's centroid: the template algorithm.",
                          .area = "examples"})

}  // namespace cgview
