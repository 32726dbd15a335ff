#include "core/mesh_report.h"

#include <algorithm>
#include <limits>
#include <numeric>

#include "core/union_find.h"

namespace cgview {

namespace {
constexpr Index kNone = std::numeric_limits<Index>::max();

int corner_of(const Tri& t, Index v) { return t[0] == v ? 0 : (t[1] == v ? 1 : 2); }
}  // namespace

MeshReport mesh_report(const Mesh& mesh) {
  MeshReport r;
  const auto& F = mesh.faces;
  const auto& P = mesh.positions;
  r.vertices = P.size();
  r.faces = F.size();
  r.bbox = bounding_box(mesh);
  const double diag = r.bbox.diagonal();
  const double area_eps = 1e-14 * diag * diag;

  // Degenerate and duplicate faces, area.
  std::vector<Tri> sorted(F.size());
  for (std::size_t f = 0; f < F.size(); ++f) {
    const Tri& t = F[f];
    const double a = 0.5 * norm(face_cross(mesh, f));
    r.area += a;
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || a <= area_eps) ++r.degenerate_faces;
    sorted[f] = t;
    std::sort(sorted[f].begin(), sorted[f].end());
  }
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 1; i < sorted.size(); ++i)
    if (sorted[i] == sorted[i - 1]) ++r.duplicate_faces;

  // Components and isolated vertices.
  std::vector<std::uint32_t> comp;
  const std::uint32_t all_components = vertex_components(mesh, comp);
  std::vector<char> used(P.size(), 0);
  for (const Tri& t : F)
    for (Index v : t) used[v] = 1;
  r.isolated_vertices = std::count(used.begin(), used.end(), 0);
  r.components = all_components - r.isolated_vertices;

  // Edges: boundary, non-manifold, orientation; fans around vertices by
  // joining the corners of two faces across each two-face edge.
  const EdgeTopology topo = edge_topology(mesh);
  r.edges = topo.edges.size();
  UnionFind corners(3 * F.size());
  UnionFind boundary(P.size());
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const auto [a, b] = topo.edges[e];
    const std::size_t deg = topo.edge_faces.degree(e);
    if (deg == 1) {
      ++r.boundary_edges;
      boundary.unite(a, b);
    } else if (deg > 2) {
      ++r.non_manifold_edges;
    } else {
      const std::uint32_t f = topo.edge_faces.begin(e)[0], g = topo.edge_faces.begin(e)[1];
      const int fa = corner_of(F[f], a), fb = corner_of(F[f], b);
      const int ga = corner_of(F[g], a), gb = corner_of(F[g], b);
      corners.unite(3 * f + fa, 3 * g + ga);
      corners.unite(3 * f + fb, 3 * g + gb);
      // In face f the side runs a->b when b follows a; g must run the other way.
      const bool f_ab = (fa + 1) % 3 == fb, g_ab = (ga + 1) % 3 == gb;
      if (f_ab == g_ab) ++r.inconsistent_edges;
    }
  }
  std::vector<char> in_boundary(P.size(), 0);
  for (std::size_t e = 0; e < topo.edges.size(); ++e)
    if (topo.edge_faces.degree(e) == 1) in_boundary[topo.edges[e][0]] = in_boundary[topo.edges[e][1]] = 1;
  for (std::uint32_t v = 0; v < P.size(); ++v)
    if (in_boundary[v] && boundary.find(v) == v) ++r.boundary_loops;

  // A vertex is manifold when all its corners fall in one fan.
  std::vector<std::uint32_t> fan(P.size(), kNone);
  std::vector<char> counted(P.size(), 0);
  for (std::uint32_t f = 0; f < F.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = F[f][k];
      if (F[f][(k + 1) % 3] == v || F[f][(k + 2) % 3] == v) continue;  // degenerate corner
      const std::uint32_t root = corners.find(3 * f + k);
      if (fan[v] == kNone) fan[v] = root;
      else if (fan[v] != root && !counted[v]) {
        counted[v] = 1;
        ++r.non_manifold_vertices;
      }
    }

  r.manifold = r.non_manifold_edges == 0 && r.non_manifold_vertices == 0;
  r.closed = r.manifold && r.boundary_edges == 0 && r.faces > 0;
  r.oriented = r.manifold && r.inconsistent_edges == 0;
  const std::int64_t used_vertices = std::int64_t(r.vertices - r.isolated_vertices);
  r.euler_characteristic = used_vertices - std::int64_t(r.edges) + std::int64_t(r.faces);
  if (r.oriented && r.faces > 0) {
    const std::int64_t twice =
        2 * std::int64_t(r.components) - *r.euler_characteristic - std::int64_t(r.boundary_loops);
    if (twice >= 0 && twice % 2 == 0) r.genus = twice / 2;
  }
  if (r.closed && r.oriented) r.volume = signed_volume(mesh);
  r.faces_inward = r.volume && *r.volume < 0;
  return r;
}

}  // namespace cgview
