#include "filters/normals.h"

#include <CGAL/Polygon_mesh_processing/compute_normal.h>

#include "core/surface_mesh.h"

namespace cgview {

NormalsResult normals(const Mesh& mesh, const NormalsParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("normals needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  ctx.progress(0.0, "halfedges");
  SurfaceMeshResult s = to_surface_mesh(mesh);
  ctx.check_cancelled();
  ctx.progress(0.3, "normals");
  auto vnormals = s.mesh.add_property_map<SurfaceMesh::Vertex_index, Kernel::Vector_3>("v:cgview_normal").first;
  CGAL::Polygon_mesh_processing::compute_vertex_normals(s.mesh, vnormals);
  ctx.check_cancelled();

  NormalsResult result;
  Mesh out = mesh;
  out.normal_faces.clear();
  out.normals.assign(mesh.num_vertices(), Vec3f{});
  for (auto v : s.mesh.vertices()) {
    const Kernel::Vector_3& n = vnormals[v];
    out.normals[v.idx()] = {float(n.x()), float(n.y()), float(n.z())};
  }
  if (s.skipped_faces > 0)
    result.warnings.push_back(std::to_string(s.skipped_faces) +
                              " non-manifold or degenerate faces could not be placed in a halfedge structure and "
                              "do not contribute to the normals");
  result.mesh = std::move(out);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(normals, normals,
                         {.title = "Vertex normals",
                          .description = "Angle-weighted unit vertex normals (CGAL Polygon Mesh Processing's "
                                         "compute_vertex_normals); the mesh comes back with one normal per vertex.",
                          .area = "filters"})

}  // namespace cgview
