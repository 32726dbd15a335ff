// CGAL_EIGEN3_ENABLED is set by CMake (algorithms/CMakeLists.txt): the jet fitting solves
// its least squares with Eigen's SVD.
#include "filters/principal_directions.h"

#include <CGAL/Monge_via_jet_fitting.h>
#include <CGAL/Simple_cartesian.h>

#include <cmath>
#include <limits>

namespace cgview {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Fitting = CGAL::Monge_via_jet_fitting<Kernel>;

Vec3f to_vec(const Kernel::Vector_3& v) { return {float(v.x()), float(v.y()), float(v.z())}; }

}  // namespace

PrincipalDirectionsResult principal_directions(const Mesh& mesh, const PrincipalDirectionsParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("principal_directions needs a mesh with faces");
  const std::size_t n = mesh.num_vertices();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  PrincipalDirectionsResult r;
  r.max_direction = {"max_direction", Location::vertex, VectorHint::direction, std::vector<Vec3f>(n, {nan, nan, nan})};
  r.min_direction = {"min_direction", Location::vertex, VectorHint::direction, std::vector<Vec3f>(n, {nan, nan, nan})};
  r.max_curvature = {"max_curvature", Location::vertex, ColorHint::symmetric, std::vector<float>(n, nan)};
  r.min_curvature = {"min_curvature", Location::vertex, ColorHint::symmetric, std::vector<float>(n, nan)};
  const Adjacency neighbours = vertex_neighbors(mesh);
  const std::vector<Vec3> normals = vertex_normals(mesh, NormalWeighting::area);
  const std::size_t needed = std::size_t((p.degree + 1) * (p.degree + 2) / 2);
  std::vector<int> seen(n, -1);  // the vertex whose ring last reached it
  std::vector<std::size_t> ring;
  std::vector<Kernel::Point_3> points;
  std::size_t missing = 0;
  Fitting fit;
  for (std::size_t v = 0; v < n; ++v) {
    if (v % 4096 == 0) {
      ctx.check_cancelled();
      ctx.progress(double(v) / double(n), "fitting");
    }
    // The vertex first (the fitting is at its point), then its rings.
    ring.assign(1, v);
    seen[v] = int(v);
    for (std::size_t first = 0, depth = 0; depth < std::size_t(p.rings); ++depth) {
      const std::size_t last = ring.size();
      for (std::size_t i = first; i < last; ++i)
        for (const std::uint32_t* m = neighbours.begin(ring[i]); m != neighbours.end(ring[i]); ++m)
          if (seen[*m] != int(v)) seen[*m] = int(v), ring.push_back(*m);
      first = last;
    }
    if (ring.size() < needed || !(norm(normals[v]) > 0)) {
      ++missing;
      continue;
    }
    points.clear();
    for (std::size_t u : ring) points.emplace_back(mesh.positions[u].x, mesh.positions[u].y, mesh.positions[u].z);
    Fitting::Monge_form form = fit(points.begin(), points.end(), std::size_t(p.degree), 2);
    // Oriented by the outward normal; CGAL's curvatures are then negative
    // where the surface bends away from it, as a sphere does: turned so that
    // a sphere of radius R gives 1/R, as the curvature filter does.
    form.comply_wrt_given_normal(Kernel::Vector_3(normals[v].x, normals[v].y, normals[v].z));
    const double k1 = -form.principal_curvatures(0), k2 = -form.principal_curvatures(1);
    const bool first_is_max = k1 >= k2;
    r.max_direction.values[v] =
        to_vec(first_is_max ? form.maximal_principal_direction() : form.minimal_principal_direction());
    r.min_direction.values[v] =
        to_vec(first_is_max ? form.minimal_principal_direction() : form.maximal_principal_direction());
    r.max_curvature.values[v] = float(std::max(k1, k2));
    r.min_curvature.values[v] = float(std::min(k1, k2));
  }
  if (missing > 0)
    r.warnings.push_back(std::to_string(missing) + " of " + std::to_string(n) +
                         " vertices have too few neighbours to fit (or no normal) and have no value");
  ctx.progress(1.0, "done");
  return r;
}

CGVIEW_REGISTER_FUNCTION(principal_directions, principal_directions,
                         {.title = "Principal curvature directions",
                          .description = "The directions of most and least curvature at each vertex, and those "
                                         "curvatures, from CGAL's jet fitting of the vertex's neighbourhood.",
                          .area = "filters"})

}  // namespace cgview
