// curvature: discrete mean and Gaussian curvature per vertex, the registered
// face of vertex_curvatures() (filters/curvature.h, Meyer et al. 2003).
#include <string>

#include "filters/curvature.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  template <class V>
  void describe(V&) {}
};

ScalarField to_field(const char* name, const std::vector<double>& values) {
  ScalarField f{name, Location::vertex, ColorHint::symmetric, {}};
  f.values.assign(values.begin(), values.end());
  return f;
}

AlgorithmResult run(const Mesh& mesh, const Params&, Context& ctx) {
  ctx.check_cancelled();
  ctx.progress(0.0, "curvature");
  const CurvatureResult c = vertex_curvatures(mesh);
  ctx.check_cancelled();
  AlgorithmResult result;
  result.artifacts.push_back({"mean_curvature", to_field("mean_curvature", c.mean)});
  result.artifacts.push_back({"gaussian_curvature", to_field("gaussian_curvature", c.gaussian)});
  if (c.degenerate_vertices > 0)
    result.warnings.push_back(std::to_string(c.degenerate_vertices) +
                              " vertices have no area (isolated or on degenerate faces only): curvature 0 there");
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(curvature, Params, run,
                          {.title = "Curvature",
                           .description = "Mean and Gaussian curvature per vertex: cotangent Laplacian and angle "
                                          "deficit over mixed Voronoi areas (Meyer et al. 2003). Mean curvature is "
                                          "positive where the surface bends away from its outward normal (a sphere).",
                           .area = "filters",
                           .outputs = {{"mean_curvature", OutputKind::scalar_field},
                                       {"gaussian_curvature", OutputKind::scalar_field}}})

}  // namespace
}  // namespace cgview
