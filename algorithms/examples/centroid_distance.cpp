// centroid_distance: the distance of each vertex from the mesh's centroid.
// The template to copy for a new algorithm: one file, registered below,
// and it appears in `cgview list`, GET /api/v1/algorithms and the viewer.
#include <algorithm>
#include <cmath>

#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  bool normalize = false;  // defaults live here, once
  double exponent = 1.0;
  template <class V>
  void describe(V& v) {
    v.boolean("normalize", normalize, {.label = "Normalize", .help = "divide by the largest distance, giving 0..1"});
    v.number("exponent", exponent,
             {.label = "Exponent", .min = 0.1, .max = 4, .help = "raise each distance to this power"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
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
  return {{{"distance", field}}, {}};
}

CGVIEW_REGISTER_ALGORITHM(centroid_distance, Params, run,
                          {.title = "Distance from the centroid",
                           .description = "Per-vertex distance from the mesh's centroid: the template algorithm.",
                           .area = "examples",
                           .outputs = {{"distance", OutputKind::scalar_field}}})

}  // namespace
}  // namespace cgview
