// sdf_segmentation: CGAL's segmentation_from_sdf_values fed with our SDF
// (sdf/sdf_segmentation.h).
#include "sdf/sdf_segmentation.h"

#include <CGAL/mesh_segmentation.h>

#include "core/surface_mesh.h"
#include "sdf/sdf_rays.h"

namespace cgview::sdf {

SdfSegmentationResult sdf_segmentation(const Mesh& mesh, const SdfSegmentationParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  // Faces keep their order in a Surface_mesh built from a manifold mesh, so
  // face i there is face i here.
  SurfaceMesh sm = manifold_surface_mesh(mesh, "sdf_segmentation");
  RawSdf raw = raw_sdf(mesh, p.sdf, {}, &ctx, 0.0, 0.7);
  SdfSegmentationResult result;
  warn_missing(raw, result.warnings);
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  std::vector<double> values = raw.values;
  postprocess(mesh, graph, values, p.sdf, ctx);
  values = normalize_linear(values);  // CGAL wants them in [0, 1]
  ctx.progress(0.85, "graph cut");
  ctx.check_cancelled();
  auto sdf_map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
  auto segment_map = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:segment", 0).first;
  for (SurfaceMesh::Face_index f : sm.faces()) sdf_map[f] = values[std::size_t(f)];
  const std::size_t segments = CGAL::segmentation_from_sdf_values(sm, sdf_map, segment_map, std::size_t(p.clusters),
                                                                  p.smoothing_lambda, p.cluster_ids);
  result.segments =
      ScalarField{"segments", Location::face, ColorHint::categorical, std::vector<float>(mesh.faces.size())};
  for (SurfaceMesh::Face_index f : sm.faces()) result.segments.values[std::size_t(f)] = float(segment_map[f]);
  result.metrics = Metrics{{"segments", double(segments)}, {"faces", double(mesh.faces.size())}};
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(sdf_segmentation, sdf_segmentation,
                         {.title = "SDF segmentation",
                          .description = "Parts of the mesh from its SDF values: CGAL's segmentation_from_sdf_values "
                                         "(Gaussian mixture clustering and a graph cut) fed with this server's SDF. "
                                         "Needs a manifold mesh.",
                          .area = "sdf",
                          .inputs = {kSdfInput}})

}  // namespace cgview::sdf
