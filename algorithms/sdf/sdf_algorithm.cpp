// sdf: the Shape Diameter Function on every face (see sdf/sdf.h), as a
// registered algorithm, with CGAL's post-processing.
#include "sdf/sdf_params.h"

#include <cmath>

namespace cgview::sdf {

namespace {

struct Params : SdfParamFields {
  template <class V>
  void describe(V& v) {
    describe_sdf(v);
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  RawSdf raw = raw_sdf(mesh, p.options(), {}, &ctx, 0.0, p.smooth ? 0.8 : 0.95);
  AlgorithmResult result;
  warn_missing(raw, result.warnings);
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  std::vector<double> values = raw.values;
  postprocess(mesh, graph, values, p, ctx);
  result.artifacts = sdf_fields(mesh, "sdf", values);
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  result.artifacts.push_back({"metrics", Metrics{{"faces", double(mesh.faces.size())},
                                                 {"rays_cast", double(raw.rays_cast)},
                                                 {"rays_accepted", double(raw.rays_accepted)},
                                                 {"faces_without_value", double(raw.missing)},
                                                 {"min", *lo},
                                                 {"max", *hi}}});
  ctx.progress(1.0, "done");
  return result;
}

}  // namespace
}  // namespace cgview::sdf

CGVIEW_REGISTER_ALGORITHM(
    sdf, cgview::sdf::Params, cgview::sdf::run,
    {.title = "Shape Diameter Function",
     .description = "The local diameter of the shape at each face, from a cone of rays cast "
                    "inwards (Shapira, Shamir and Cohen-Or 2008); ray casting on Embree, on every core. "
                    "Rays escaping through holes of an open mesh are dropped.",
     .area = "sdf",
     .outputs = {{"sdf", cgview::OutputKind::scalar_field},
                 {"sdf_normalized", cgview::OutputKind::scalar_field},
                 {"sdf_vertex", cgview::OutputKind::scalar_field},
                 {"metrics", cgview::OutputKind::metrics}},
     .inputs = {cgview::sdf::kSdfInput}});
