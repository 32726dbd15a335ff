#include "filters/curvature.h"

#include "filters/vertex_curvatures.h"

namespace cgview {
namespace {

ScalarField to_field(const char* name, const std::vector<double>& values) {
  ScalarField f{name, Location::vertex, ColorHint::symmetric, {}};
  f.values.assign(values.begin(), values.end());
  return f;
}

}  // namespace

CurvatureResult curvature(const Mesh& mesh, const CurvatureParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.check_cancelled();
  ctx.progress(0.0, "curvature");
  const VertexCurvatures c = vertex_curvatures(mesh);
  ctx.check_cancelled();
  CurvatureResult result;
  result.mean_curvature = to_field("mean_curvature", c.mean);
  result.gaussian_curvature = to_field("gaussian_curvature", c.gaussian);
  if (c.degenerate_vertices > 0)
    result.warnings.push_back(std::to_string(c.degenerate_vertices) +
                              " vertices have no area (isolated or on degenerate faces only): curvature 0 there");
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(curvature, curvature,
                         {.title = "Curvature",
                          .description = "Mean and Gaussian curvature per vertex: cotangent Laplacian and angle "
                                         "deficit over mixed Voronoi areas (Meyer et al. 2003). Mean curvature is "
                                         "positive where the surface bends away from its outward normal (a sphere).",
                          .area = "filters"})

}  // namespace cgview
