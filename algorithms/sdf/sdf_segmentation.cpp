// sdf_segmentation: CGAL's segmentation_from_sdf_values fed with our SDF
// (sdf/sdf_segmentation.h).
#include "sdf/sdf_segmentation.h"

#include <CGAL/mesh_segmentation.h>

#include <cstdint>
#include <numeric>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "sdf/sdf_rays.h"

namespace cgview::sdf {

SdfSegmentationResult sdf_segmentation(const Mesh& mesh, const SdfSegmentationParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  // Faces keep their order in a Surface_mesh built from a manifold mesh, so
  // face i there is face i here; a repaired copy's faces are found by their
  // corners.  The SDF is measured on the mesh as it is (its rays need no
  // halfedges); only the graph cut runs on the copy.
  SdfSegmentationResult result;
  bool repaired = false;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "sdf_segmentation", p.repair, result.warnings, &repaired);
  std::vector<std::int64_t> face_of(mesh.faces.size());
  if (repaired) face_of = faces_after_repair(mesh, sm);
  else std::iota(face_of.begin(), face_of.end(), std::int64_t(0));
  Adjacency graph;
  RawSdf raw = raw_sdf(mesh, p.sdf, graph, &ctx, 0.0, 0.7);
  warn_missing(raw, result.warnings);
  std::vector<double> values = raw.values;
  postprocess(mesh, graph, values, p.sdf, ctx);
  values = normalize_linear(values);  // CGAL wants them in [0, 1]
  ctx.progress(0.85, "graph cut");
  ctx.check_cancelled();
  auto sdf_map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
  auto segment_map = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:segment", 0).first;
  for (std::size_t i = face_of.size(); i-- > 0;)  // a duplicate face's value: the first's
    if (face_of[i] >= 0) sdf_map[SurfaceMesh::Face_index(SurfaceMesh::size_type(face_of[i]))] = values[i];
  const std::size_t segments = CGAL::segmentation_from_sdf_values(sm, sdf_map, segment_map, std::size_t(p.clusters),
                                                                  p.smoothing_lambda, p.cluster_ids);
  result.segments =
      ScalarField{"segments", Location::face, ColorHint::categorical, std::vector<float>(mesh.faces.size())};
  std::vector<float>& seg = result.segments.values;
  // A face the repair removed takes the segment of a neighbour that has one
  // (breadth first), or 0 if none has.
  std::vector<std::uint8_t> known(mesh.faces.size(), 0);
  std::vector<std::size_t> queue;
  for (std::size_t i = 0; i < face_of.size(); ++i)
    if (face_of[i] >= 0) {
      seg[i] = float(segment_map[SurfaceMesh::Face_index(SurfaceMesh::size_type(face_of[i]))]);
      known[i] = 1;
      if (repaired) queue.push_back(i);
    }
  for (std::size_t q = 0; q < queue.size(); ++q)
    for (const std::uint32_t* m = graph.begin(queue[q]); m != graph.end(queue[q]); ++m)
      if (!known[*m]) seg[*m] = seg[queue[q]], known[*m] = 1, queue.push_back(*m);
  result.metrics = Metrics{{"segments", double(segments)}, {"faces", double(mesh.faces.size())}};
  ray_metrics(raw, result.metrics);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(sdf_segmentation, sdf_segmentation,
                         {.title = "SDF segmentation",
                          .description = "Parts of the mesh from its SDF values: CGAL's segmentation_from_sdf_values "
                                         "(Gaussian mixture clustering and a graph cut) fed with this server's SDF. "
                                         "A mesh that is not manifold is cut on a repaired copy.",
                          .area = "sdf",
                          .inputs = {kSdfInput}})

}  // namespace cgview::sdf
