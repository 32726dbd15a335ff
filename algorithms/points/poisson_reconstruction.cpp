#include "points/poisson_reconstruction.h"

#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <memory>
#include <utility>

#include "core/orient.h"
#include "core/surface_mesh.h"
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
    const EstimateNormalsParams defaults;
    EstimateNormalsResult e = estimate_normals(cloud, defaults);
    estimated = std::move(e.points);
    with_normals = &estimated;
    // The defaults named from their own description, so that the warning
    // says what ran whatever estimate_normals' defaults become.
    std::string how;
    for (const ParamSpec& s : detail::described(defaults))
      how += (how.empty() ? "" : ", ") + s.name + " " + to_string(s.default_value);
    result.warnings.push_back("the cloud has no normals: they were estimated (estimate_normals with " + how +
                              "); run estimate_normals yourself to choose how, or bring the scanner's");
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
  // The mesher starts from points where segments from the inner point
  // cross the surface (20 by default): on a thin shape (the 44k points of
  // refined_elephant, about one run in eight) none of their Delaunay facets
  // may cross it, and the complex stays empty (whereupon CGAL 5.5's
  // facets_in_complex_2_to_triangle_mesh reads the first of no facets: a
  // crash); more starting points then.
  struct Meshed {
    Triangulation tr;
    Complex c2t3{tr};
  };
  std::unique_ptr<Meshed> meshed;
  for (const int initial : {20, 200, 2000}) {
    meshed = std::make_unique<Meshed>();
    CGAL::make_surface_mesh(meshed->c2t3, surface, criteria, CGAL::Manifold_with_boundary_tag(), initial);
    if (meshed->c2t3.number_of_facets() > 0) break;
    ctx.check_cancelled();
  }
  const Complex& c2t3 = meshed->c2t3;
  if (c2t3.number_of_facets() == 0)
    throw InvalidInput("poisson_reconstruction: the mesher found no surface (do the normals point consistently?)");
  ctx.check_cancelled();

  ctx.progress(0.95, "mesh");
  SurfaceMesh sm;
  CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, sm);
  const bool closed = CGAL::is_closed(sm);
  result.mesh = from_surface_mesh(sm);
  orient_outward_in_place(result.mesh);
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
