#include "sdf/sdf.h"

#include <algorithm>
#include <cmath>

#include "sdf/sdf_rays.h"

namespace cgview::sdf {

SdfResult sdf(const Mesh& mesh, const SdfParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  Adjacency graph;
  RawSdf raw = raw_sdf(mesh, p, graph, &ctx, 0.0, p.smooth ? 0.8 : 0.95);
  SdfResult result;
  warn_missing(raw, result.warnings);
  std::vector<double> values = raw.values;
  postprocess(mesh, graph, values, p, ctx);
  result.sdf = ScalarField{"sdf", Location::face, ColorHint::standard, {values.begin(), values.end()}};
  const std::vector<double> normalized = normalize_linear(values);
  result.sdf_normalized =
      ScalarField{"sdf_normalized", Location::face, ColorHint::standard, {normalized.begin(), normalized.end()}};
  result.sdf_vertex = face_to_vertex(mesh, result.sdf);
  result.sdf_vertex.name = "sdf_vertex";
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  result.metrics = Metrics{{"faces", double(mesh.faces.size())},
                           {"rays_cast", double(raw.rays_cast)},
                           {"rays_accepted", double(raw.rays_accepted)},
                           {"faces_without_value", double(raw.missing)},
                           {"min", *lo},
                           {"max", *hi}};
  ray_metrics(raw, result.metrics);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(sdf, sdf,
                         {.title = "Shape Diameter Function",
                          .description = "The local diameter of the shape at each face, from a cone of rays cast "
                                         "inwards (Shapira, Shamir and Cohen-Or 2008); ray casting on Embree, on "
                                         "every core, or on the GPU where there is one. Rays escaping through "
                                         "holes of an open mesh are dropped. With uniform weights and the MAD "
                                         "outlier rule, the values are CGAL's sdf_values.",
                          .area = "sdf",
                          .inputs = {kSdfInput}})

}  // namespace cgview::sdf
