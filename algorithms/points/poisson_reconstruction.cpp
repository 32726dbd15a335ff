#include "points/poisson_reconstruction.h"

#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <unordered_map>
#include <utility>

#include "core/orient.h"
#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "points/estimate_normals.h"

namespace cgview {
namespace {

using PointNormal = std::pair<Point3, Kernel::Vector_3>;
using PointMap = CGAL::First_of_pair_property_map<PointNormal>;
using NormalMap = CGAL::Second_of_pair_property_map<PointNormal>;
using Poisson = CGAL::Poisson_reconstruction_function<Kernel>;
using Triangulation = CGAL::Surface_mesher::Surface_mesh_default_triangulation_3_generator<Kernel>::Type;
using Complex = CGAL::Surface_mesh_complex_2_in_triangulation_3<Triangulation>;
using ImplicitSurface = CGAL::Implicit_surface_3<Kernel, Poisson>;

}  // namespace

PoissonReconstructionResult poisson_reconstruction(const PointCloud& cloud, const PoissonReconstructionParams& p,
                                                   Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  cloud.validate();
  if (cloud.size() < 6)
    throw InvalidInput("poisson_reconstruction needs at least 6 points; the cloud has " + std::to_string(cloud.size()));
  PoissonReconstructionResult result;
  ctx.progress(0.0, "normals");
  PointCloud estimated;
  const PointCloud* with_normals = &cloud;
  if (!cloud.has_normals()) {
    EstimateNormalsResult e = estimate_normals(cloud);
    estimated = std::move(e.points);
    with_normals = &estimated;
    result.warnings.push_back(
        "the cloud has no normals: they were estimated (estimate_normals: jet, 18 neighbours, oriented); run "
        "estimate_normals yourself to choose how, or bring the scanner's");
    for (std::string& w : e.warnings) result.warnings.push_back("estimate_normals: " + std::move(w));
  }
  ctx.check_cancelled();

  std::vector<PointNormal> points;
  points.reserve(cloud.size());
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const Vec3& q = with_normals->positions[i];
    const Vec3f& n = with_normals->normals[i];
    points.emplace_back(Point3(q.x, q.y, q.z), Kernel::Vector_3(n.x, n.y, n.z));
  }
  ctx.progress(0.1, "spacing");
  const double spacing =
      CGAL::compute_average_spacing<CGAL::Sequential_tag>(points, 6, CGAL::parameters::point_map(PointMap()));
  if (!(spacing > 0)) throw InvalidInput("poisson_reconstruction: the points' average spacing is 0 (they coincide)");
  ctx.check_cancelled();

  ctx.progress(0.15, "solving");
  Poisson function(points.begin(), points.end(), PointMap(), NormalMap());
  if (!function.compute_implicit_function())
    throw InvalidInput(
        "poisson_reconstruction: the Poisson solver found no implicit function (are the points coplanar, or the "
        "normals inconsistent?)");
  ctx.check_cancelled();

  ctx.progress(0.5, "meshing");
  // As poisson_surface_reconstruction_delaunay does it.
  const Point3 inner = function.get_inner_point();
  const Kernel::Sphere_3 bounding = function.bounding_sphere();
  const double sphere_radius = 5.0 * std::sqrt(bounding.squared_radius());
  const double dichotomy_error = p.distance * spacing / 1000.0;
  ImplicitSurface surface(function, Kernel::Sphere_3(inner, sphere_radius * sphere_radius),
                          dichotomy_error / sphere_radius);
  const CGAL::Surface_mesh_default_criteria_3<Triangulation> criteria(p.angle, p.radius * spacing,
                                                                      p.distance * spacing);
  Triangulation tr;
  Complex c2t3(tr);
  CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_with_boundary_tag());
  if (tr.number_of_vertices() == 0)
    throw InvalidInput("poisson_reconstruction: the mesher found no surface (do the normals point consistently?)");
  ctx.check_cancelled();

  ctx.progress(0.95, "mesh");
  // Not CGAL's facets_in_complex_2_to_triangle_mesh: in CGAL 5.5 its walk
  // over the facets ran past their end now and then (a crash: twice in
  // about 16 runs on the 44k points of refined_elephant).  The facets as a
  // soup, oriented and made a halfedge mesh by the repair's soup tools.
  Mesh soup;
  std::unordered_map<Triangulation::Vertex_handle, Index> index;
  for (auto f = c2t3.facets_begin(); f != c2t3.facets_end(); ++f) {
    Tri t;
    for (int j = 0; j < 3; ++j) {
      const Triangulation::Vertex_handle v = f->first->vertex(tr.vertex_triple_index(f->second, j));
      const auto [at, fresh] = index.try_emplace(v, Index(soup.positions.size()));
      if (fresh) soup.positions.push_back({v->point().x(), v->point().y(), v->point().z()});
      t[j] = at->second;
    }
    soup.faces.push_back(t);
  }
  RepairReport repair;
  const SurfaceMesh sm = repair_to_surface_mesh(soup, false, repair);
  const bool closed = CGAL::is_closed(sm);
  result.mesh = from_surface_mesh(sm);
  orient_outward_in_place(result.mesh);
  if (repair.vertices_duplicated > 0)
    result.warnings.push_back(std::to_string(repair.vertices_duplicated) +
                              " vertices of the surface were duplicated where it touched itself (non-manifold)");
  if (!closed)
    result.warnings.push_back(
        "the surface is not closed (the mesher left holes): more points, or a larger approximation error, may "
        "close it");
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(
    poisson_reconstruction,
    [](const Inputs& in, const PoissonReconstructionParams& p, Context* c) {
      return poisson_reconstruction(in.points("points"), p, c);
    },
    {.title = "Poisson reconstruction",
     .description = "A closed surface through a point cloud with normals (CGAL's Poisson surface reconstruction); "
                    "a cloud without normals gets them from estimate_normals first.",
     .area = "points",
     .inputs = {{.name = "points",
                 .kind = OutputKind::points,
                 .help = "the point cloud, best with outward normals (a mesh's vertices may stand for one)"}}})

}  // namespace cgview
