// sdf_segmentation: segment ids per face from our SDF values, by CGAL's
// segmentation_from_sdf_values (soft clustering of the log-normalized values
// by a Gaussian mixture, then a graph cut that prefers cuts along concave
// edges: Shapira et al. 2008, section 4).
#include <CGAL/mesh_segmentation.h>

#include <set>

#include "core/surface_mesh.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {
namespace {

struct Params : SdfParamFields {
  int clusters = 5;
  double smoothing_lambda = 0.26;
  bool cluster_ids = false;
  template <class V>
  void describe(V& v) {
    v.integer("clusters", clusters,
              {.label = "Clusters",
               .min = 1,
               .max = 32,
               .help = "levels of the soft clustering of SDF values (CGAL's number_of_clusters)"});
    v.number("smoothing_lambda", smoothing_lambda,
             {.label = "Smoothing",
              .min = 0,
              .max = 1,
              .help = "weight of the surface's concave edges in the graph cut (0: none)"});
    v.boolean(
        "cluster_ids", cluster_ids,
        {.label = "Cluster ids", .help = "give each face its cluster (SDF level) instead of its connected segment"});
    describe_sdf(v);
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  // Faces keep their order in a Surface_mesh built from a manifold mesh, so
  // face i there is face i here.
  SurfaceMesh sm = manifold_surface_mesh(mesh, "sdf_segmentation");
  RawSdf raw = raw_sdf(mesh, p.options(), {}, &ctx, 0.0, 0.7);
  AlgorithmResult result;
  warn_missing(raw, result.warnings);
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  std::vector<double> values = raw.values;
  postprocess(mesh, graph, values, p, ctx);
  values = normalize_linear(values);  // CGAL wants them in [0, 1]
  ctx.progress(0.85, "graph cut");
  ctx.check_cancelled();
  auto sdf_map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
  auto segment_map = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:segment", 0).first;
  for (SurfaceMesh::Face_index f : sm.faces()) sdf_map[f] = values[std::size_t(f)];
  const std::size_t segments = CGAL::segmentation_from_sdf_values(sm, sdf_map, segment_map, std::size_t(p.clusters),
                                                                  p.smoothing_lambda, p.cluster_ids);
  ScalarField field{"segments", Location::face, ColorHint::categorical, std::vector<float>(mesh.faces.size())};
  for (SurfaceMesh::Face_index f : sm.faces()) field.values[std::size_t(f)] = float(segment_map[f]);
  result.artifacts.push_back({"segments", std::move(field)});
  result.artifacts.push_back(
      {"metrics", Metrics{{"segments", double(segments)}, {"faces", double(mesh.faces.size())}}});
  ctx.progress(1.0, "done");
  return result;
}

}  // namespace
}  // namespace cgview::sdf

CGVIEW_REGISTER_ALGORITHM(sdf_segmentation, cgview::sdf::Params, cgview::sdf::run,
                          {.title = "SDF segmentation",
                           .description = "Parts of the mesh from its SDF values: CGAL's segmentation_from_sdf_values "
                                          "(Gaussian mixture clustering and a graph cut) fed with this server's SDF. "
                                          "Needs a manifold mesh.",
                           .area = "sdf",
                           .outputs = {{"segments", cgview::OutputKind::scalar_field},
                                       {"metrics", cgview::OutputKind::metrics}},
                           .inputs = {cgview::sdf::kSdfInput}});
