#include "filters/curvature.h"

#include <string>

#include "core/errors.h"
#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "filters/vertex_curvatures.h"

namespace cgview {
namespace {

ScalarField to_field(const char* name, const std::vector<double>& values) {
  ScalarField f{name, Location::vertex, ColorHint::symmetric, {}};
  f.values.assign(values.begin(), values.end());
  return f;
}

std::size_t edges_of_many_faces(const Mesh& mesh) {
  const EdgeTopology topo = edge_topology(mesh);
  std::size_t n = 0;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) n += topo.edge_faces.degree(e) > 2;
  return n;
}

// The curvatures of a repaired copy of `mesh`, per vertex of `mesh`: the
// mean over the copy's vertices at its position (0 for a vertex the repair
// removed, as for any vertex without area).
VertexCurvatures curvatures_of_repaired(const Mesh& mesh, std::vector<std::string>& warnings) {
  const SurfaceMesh sm = halfedge_mesh_for(mesh, "curvature", true, warnings);
  const VertexCurvatures c = vertex_curvatures(from_surface_mesh(sm));
  // from_surface_mesh numbers the copy's vertices in sm's order.
  std::vector<std::size_t> index_of(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  std::size_t next = 0;
  for (auto v : sm.vertices()) index_of[v.idx()] = next++;
  VertexCurvatures out;
  out.mean.assign(mesh.num_vertices(), 0.0);
  out.gaussian.assign(mesh.num_vertices(), 0.0);
  out.area.assign(mesh.num_vertices(), 0.0);
  out.degenerate_vertices = c.degenerate_vertices;
  const auto copies = vertices_after_repair(mesh, sm);
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (copies[i].empty()) continue;
    for (auto v : copies[i]) {
      const std::size_t j = index_of[v.idx()];
      out.mean[i] += c.mean[j], out.gaussian[i] += c.gaussian[j], out.area[i] += c.area[j];
    }
    out.mean[i] /= double(copies[i].size()), out.gaussian[i] /= double(copies[i].size());
  }
  return out;
}

}  // namespace

CurvatureResult curvature(const Mesh& mesh, const CurvatureParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.check_cancelled();
  ctx.progress(0.0, "curvature");
  CurvatureResult result;
  std::size_t non_manifold = 0;
  if (mesh.num_faces() > 0) {
    mesh.validate();
    non_manifold = edges_of_many_faces(mesh);
  }
  if (non_manifold > 0 && !p.repair)
    throw InvalidInput("curvature needs a manifold mesh: " + std::to_string(non_manifold) +
                       " edges are shared by more than two faces; set 'repair' to repair it first, or run repair "
                       "on it");
  const VertexCurvatures c = non_manifold > 0 ? curvatures_of_repaired(mesh, result.warnings) : vertex_curvatures(mesh);
  ctx.check_cancelled();
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
