#include "core/surface_mesh.h"

#include <CGAL/IO/Color.h>

#include "core/errors.h"

namespace cgview {

SurfaceMeshResult to_surface_mesh(const Mesh& mesh) {
  SurfaceMeshResult r;
  SurfaceMesh& sm = r.mesh;
  sm.reserve(SurfaceMesh::size_type(mesh.num_vertices()), SurfaceMesh::size_type(3 * mesh.num_faces() / 2),
             SurfaceMesh::size_type(mesh.num_faces()));
  for (const Vec3& p : mesh.positions) sm.add_vertex(Point3(p.x, p.y, p.z));
  for (const Tri& t : mesh.faces) {
    const auto f =
        sm.add_face(SurfaceMesh::Vertex_index(t[0]), SurfaceMesh::Vertex_index(t[1]), SurfaceMesh::Vertex_index(t[2]));
    if (f == SurfaceMesh::null_face()) ++r.skipped_faces;
  }
  if (mesh.has_normals() && mesh.normal_faces.empty()) {
    auto [nm, created] = sm.add_property_map<SurfaceMesh::Vertex_index, Kernel::Vector_3>("v:normal");
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
      nm[SurfaceMesh::Vertex_index(Index(v))] = {mesh.normals[v].x, mesh.normals[v].y, mesh.normals[v].z};
  }
  if (mesh.has_colors()) {
    auto [cm, created] = sm.add_property_map<SurfaceMesh::Vertex_index, CGAL::IO::Color>("v:color");
    for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
      const Color c = mesh.colors[v];
      cm[SurfaceMesh::Vertex_index(Index(v))] = CGAL::IO::Color(c.r, c.g, c.b, c.a);
    }
  }
  return r;
}

SurfaceMesh manifold_surface_mesh(const Mesh& mesh, const char* who, const char* remedy) {
  SurfaceMeshResult r = to_surface_mesh(mesh);
  if (r.skipped_faces > 0)
    throw InvalidInput(std::string(who) + " needs a manifold mesh: " + std::to_string(r.skipped_faces) +
                       " faces could not be placed in a halfedge structure (non-manifold or degenerate); " + remedy);
  return std::move(r.mesh);
}

Mesh from_surface_mesh(const SurfaceMesh& sm) {
  Mesh out;
  std::vector<Index> id(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  for (auto v : sm.vertices()) {
    id[v.idx()] = Index(out.positions.size());
    const Point3& p = sm.point(v);
    out.positions.push_back({p.x(), p.y(), p.z()});
  }
  for (auto f : sm.faces()) {
    Tri t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(sm.halfedge(f), sm)) {
      if (k < 3) t[k] = id[v.idx()];
      ++k;
    }
    if (k == 3) out.faces.push_back(t);
  }
  return out;
}

}  // namespace cgview
