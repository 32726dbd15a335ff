#include "filters/vertex_curvatures.h"

#include <cmath>
#include <numbers>
#include <string>

#include "core/errors.h"

namespace cgview {

VertexCurvatures vertex_curvatures(const Mesh& mesh) {
  if (mesh.num_faces() == 0) throw InvalidInput("curvature needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  const EdgeTopology topo = edge_topology(mesh);
  std::size_t non_manifold = 0;
  std::vector<char> border(mesh.num_vertices(), 0);
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const std::size_t n = topo.edge_faces.degree(e);
    if (n > 2) ++non_manifold;
    if (n == 1) border[topo.edges[e][0]] = border[topo.edges[e][1]] = 1;
  }
  if (non_manifold > 0)
    throw InvalidInput("curvature needs a manifold mesh: " + std::to_string(non_manifold) +
                       " edges are shared by more than two faces");

  const std::size_t nv = mesh.num_vertices();
  const auto& P = mesh.positions;
  std::vector<Vec3> laplace(nv, Vec3{});  // sum_j (cot a + cot b)(x_j - x_i)
  std::vector<double> angle_sum(nv, 0.0);
  VertexCurvatures r;
  r.area.assign(nv, 0.0);

  for (const Tri& t : mesh.faces) {
    const Vec3 x[3] = {P[t[0]], P[t[1]], P[t[2]]};
    const double twice_area = norm(cross(x[1] - x[0], x[2] - x[0]));
    if (!(twice_area > 0)) continue;
    double cot[3], angle[3];
    for (int k = 0; k < 3; ++k) {
      const Vec3 a = x[(k + 1) % 3] - x[k], b = x[(k + 2) % 3] - x[k];
      cot[k] = dot(a, b) / twice_area;
      angle[k] = std::atan2(twice_area, dot(a, b));
    }
    const double area = twice_area / 2;
    const bool obtuse = cot[0] < 0 || cot[1] < 0 || cot[2] < 0;
    for (int k = 0; k < 3; ++k) {
      const int i = (k + 1) % 3, j = (k + 2) % 3;  // the edge (i, j) opposite corner k
      laplace[t[i]] += (x[j] - x[i]) * cot[k];
      laplace[t[j]] += (x[i] - x[j]) * cot[k];
      angle_sum[t[k]] += angle[k];
      double a;
      if (!obtuse) {
        // Voronoi area of corner k: its two sides, each weighted by the cot of the angle opposite it.
        a = (dot(x[i] - x[k], x[i] - x[k]) * cot[j] + dot(x[j] - x[k], x[j] - x[k]) * cot[i]) / 8;
      } else {
        a = cot[k] < 0 ? area / 2 : area / 4;
      }
      r.area[t[k]] += a;
    }
  }

  const std::vector<Vec3> normals = vertex_normals(mesh, NormalWeighting::angle);
  r.mean.assign(nv, 0.0);
  r.gaussian.assign(nv, 0.0);
  const double pi = std::numbers::pi;
  for (std::size_t v = 0; v < nv; ++v) {
    const double a = r.area[v];
    if (!(a > 0)) {
      ++r.degenerate_vertices;
      continue;
    }
    r.mean[v] = -dot(laplace[v], normals[v]) / (4 * a);
    r.gaussian[v] = ((border[v] ? pi : 2 * pi) - angle_sum[v]) / a;
  }
  return r;
}

}  // namespace cgview
