#include "core/surface_mesh.h"

#include <CGAL/IO/Color.h>

#include "core/errors.h"

namespace cgview {
namespace {

using V = SurfaceMesh::Vertex_index;
using H = SurfaceMesh::Halfedge_index;
using F = SurfaceMesh::Face_index;
constexpr Index kNoEdge = ~Index(0);

// The halfedge structure of an oriented 2-manifold triangle mesh, set
// directly from its edges (core/mesh.h's edge_topology) in linear time:
// Surface_mesh::add_face searches each vertex's fan and relinks borders, three
// to four times slower on a million faces.  Returns false, leaving `sm` to be
// cleared, where the mesh is not such a mesh (a degenerate face, an edge of
// three faces or of two faces the same way round, a vertex where two fans
// meet); add_face then decides face by face.
bool build_oriented_manifold(const Mesh& mesh, SurfaceMesh& sm) {
  const EdgeTopology topo = edge_topology(mesh);
  const std::size_t nv = mesh.num_vertices(), nf = mesh.num_faces();
  for (std::size_t e = 0; e < topo.edges.size(); ++e) sm.add_edge();  // halfedges 2e (a->b) and 2e+1 (b->a)
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    sm.set_target(H(SurfaceMesh::size_type(2 * e)), V(topo.edges[e][1]));
    sm.set_target(H(SurfaceMesh::size_type(2 * e + 1)), V(topo.edges[e][0]));
  }
  std::vector<std::uint8_t> used(2 * topo.edges.size(), 0);
  for (std::size_t fi = 0; fi < nf; ++fi) {
    const Tri& t = mesh.faces[fi];
    const F f = sm.add_face();
    H h[3];
    for (int k = 0; k < 3; ++k) {
      const Index e = topo.face_edges[fi][k];
      if (e == kNoEdge || topo.edge_faces.degree(e) > 2) return false;
      const std::size_t hi = 2 * std::size_t(e) + (topo.edges[e][0] == t[k] ? 0 : 1);
      if (used[hi]++) return false;  // two faces use the edge the same way round
      h[k] = H(SurfaceMesh::size_type(hi));
      sm.set_face(h[k], f);
    }
    for (int k = 0; k < 3; ++k) sm.set_next(h[k], h[(k + 1) % 3]);
    sm.set_halfedge(f, h[0]);
  }
  // Each vertex: an incoming halfedge, the border one where there is one, and
  // at most one border halfedge leaving it (else two fans meet there).
  std::vector<H> border_out(nv, SurfaceMesh::null_halfedge());
  for (std::size_t hi = 0; hi < used.size(); ++hi) {
    const H h{SurfaceMesh::size_type(hi)};
    const V to = sm.target(h);
    if (used[hi]) {
      if (sm.halfedge(to) == SurfaceMesh::null_halfedge()) sm.set_halfedge(to, h);
      continue;
    }
    const V from = sm.target(sm.opposite(h));
    if (border_out[std::size_t(from)] != SurfaceMesh::null_halfedge()) return false;
    border_out[std::size_t(from)] = h;
  }
  for (std::size_t hi = 0; hi < used.size(); ++hi) {
    if (used[hi]) continue;
    const H h{SurfaceMesh::size_type(hi)};
    const V to = sm.target(h);
    sm.set_next(h, border_out[std::size_t(to)]);
    sm.set_halfedge(to, h);
  }
  // A vertex whose faces form more than one fan: walking around it from its
  // halfedge misses some.  (A closed fan pinched to another has no border.)
  std::vector<std::uint32_t> faces_at(nv, 0);
  for (const Tri& t : mesh.faces)
    for (int k = 0; k < 3; ++k) ++faces_at[t[k]];
  for (std::size_t v = 0; v < nv; ++v) {
    const H start = sm.halfedge(V(Index(v)));
    if (start == SurfaceMesh::null_halfedge()) continue;
    std::uint32_t n = 0;
    H h = start;
    do {
      if (sm.face(h) != SurfaceMesh::null_face()) ++n;
      h = sm.opposite(sm.next(h));
      if (n > faces_at[v]) return false;
    } while (h != start);
    if (n != faces_at[v]) return false;
  }
  return true;
}

}  // namespace

SurfaceMeshResult to_surface_mesh(const Mesh& mesh) {
  SurfaceMeshResult r;
  SurfaceMesh& sm = r.mesh;
  const auto reserve = [&] {
    sm.reserve(SurfaceMesh::size_type(mesh.num_vertices()), SurfaceMesh::size_type(3 * mesh.num_faces() / 2),
               SurfaceMesh::size_type(mesh.num_faces()));
    for (const Vec3& p : mesh.positions) sm.add_vertex(Point3(p.x, p.y, p.z));
  };
  reserve();
  if (!build_oriented_manifold(mesh, sm)) {
    sm.clear();
    reserve();
    for (const Tri& t : mesh.faces) {
      const auto f = sm.add_face(V(t[0]), V(t[1]), V(t[2]));
      if (f == SurfaceMesh::null_face()) ++r.skipped_faces;
    }
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

SurfaceMesh manifold_surface_mesh(const Mesh& mesh, const char* who) {
  SurfaceMeshResult r = to_surface_mesh(mesh);
  if (r.skipped_faces > 0)
    throw InvalidInput(std::string(who) + " needs a manifold mesh: " + std::to_string(r.skipped_faces) +
                       " faces could not be placed in a halfedge structure (non-manifold or degenerate)");
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
