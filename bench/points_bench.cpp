// Point clouds: estimate_normals and poisson_reconstruction run through the
// registry (find_algorithm(name).run, which converts the PointCloud to
// CGAL's points and back, and checks) against direct calls of the same
// CGAL functions with the same settings on CGAL points already in memory
// (converted once, outside the timing): jet_estimate_normals or
// pca_estimate_normals then mst_orient_normals (18 neighbours), and
// compute_average_spacing then the steps of
// poisson_surface_reconstruction_delaunay (its mesh made only of a complex
// with facets: CGAL's function crashes on an empty one).
// Clouds: the vertices of sample meshes (points_of), with the mesh's
// vertex normals for Poisson.  Prints a Markdown table with the ratio.
//
//   build/bin/points_bench [--repeat N] [--quick] [--only elephant,refined_elephant,...]
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/pca_estimate_normals.h>
#include <CGAL/IO/facets_in_complex_2_to_triangle_mesh.h>
#include <CGAL/Implicit_surface_3.h>
#include <CGAL/Poisson_reconstruction_function.h>
#include <CGAL/Surface_mesh_default_triangulation_3.h>
#include <CGAL/make_surface_mesh.h>
#include <CGAL/property_map.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "bench_util.h"
#include "core/point_cloud.h"
#include "core/surface_mesh.h"
#include "filters/normals.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"

using namespace cgview;

namespace {

using PointNormal = std::pair<Point3, Kernel::Vector_3>;
using PointMap = CGAL::First_of_pair_property_map<PointNormal>;
using NormalMap = CGAL::Second_of_pair_property_map<PointNormal>;
using Poisson = CGAL::Poisson_reconstruction_function<Kernel>;
using Triangulation = CGAL::Surface_mesher::Surface_mesh_default_triangulation_3_generator<Kernel>::Type;
using Complex = CGAL::Surface_mesh_complex_2_in_triangulation_3<Triangulation>;
using Surface = CGAL::Implicit_surface_3<Kernel, Poisson>;

std::vector<PointNormal> cgal_points(const PointCloud& c) {
  std::vector<PointNormal> pts;
  for (std::size_t i = 0; i < c.size(); ++i) {
    const Vec3 q = c.positions[i];
    const Vec3 n = c.has_normals() ? to_double(c.normals[i]) : Vec3{0, 0, 0};
    pts.emplace_back(Point3(q.x, q.y, q.z), Kernel::Vector_3(n.x, n.y, n.z));
  }
  return pts;
}

double ours(const std::string& name, const PointCloud& cloud, const std::map<std::string, ParamValue>& params,
            int repeat) {
  const Algorithm& a = find_algorithm(name);
  Inputs in;
  in.add("points", cloud);
  Context ctx;
  return bench::best_seconds(repeat, [&] { (void)a.run(in, params, ctx); });
}

void row(const char* algorithm, const char* settings, const std::string& cloud, std::size_t n, double t_ours,
         double t_cgal) {
  std::printf("| %s | %s | %s | %zu | %.3f | %.3f | %.2fx |\n", algorithm, settings, cloud.c_str(), n, t_ours, t_cgal,
              t_ours / t_cgal);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const bench::Options opt = bench::parse_options(argc, argv, "points_bench");
  std::vector<std::string> names{"elephant", "refined_elephant", "armadillo"};
  if (opt.quick) names = {"elephant"};
  std::printf("| algorithm | settings | cloud (vertices of) | points | ours (s) | CGAL direct (s) | ratio |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const std::string& name : names) {
    if (!opt.wants(name)) continue;
    const auto path = resolve_mesh_path(name);
    if (!path) {
      std::fprintf(stderr, "points_bench: no sample mesh %s (install libcgal-demo)\n", name.c_str());
      return 1;
    }
    const Mesh mesh = read_mesh(*path);
    PointCloud bare = points_of(mesh);
    bare.normals.clear();
    const PointCloud with_normals = points_of(normals(mesh).mesh);
    const auto params = CGAL::parameters::point_map(PointMap()).normal_map(NormalMap());

    for (const bool jet : {true, false}) {
      const double t_ours = ours("estimate_normals", bare, {{"method", std::string(jet ? "jet" : "pca")}}, opt.repeat);
      const std::vector<PointNormal> fresh = cgal_points(bare);
      std::vector<PointNormal> pts;
      const double t_cgal = bench::best_seconds(
          opt.repeat, [&] { pts = fresh; },
          [&] {
            if (jet) CGAL::jet_estimate_normals<CGAL::Sequential_tag>(pts, 18, params);
            else CGAL::pca_estimate_normals<CGAL::Sequential_tag>(pts, 18, params);
            (void)CGAL::mst_orient_normals(pts, 18, params);
          });
      row("estimate_normals", jet ? "jet, 18 neighbours, oriented" : "pca, 18 neighbours, oriented", name, bare.size(),
          t_ours, t_cgal);
    }

    const double t_ours = ours("poisson_reconstruction", with_normals, {}, opt.repeat);
    const std::vector<PointNormal> pts = cgal_points(with_normals);
    // The steps of poisson_surface_reconstruction_delaunay, which crashes
    // when the complex is empty (points/poisson_reconstruction.cpp): the
    // mesh made only of a complex with facets.
    const double t_cgal = bench::best_seconds(opt.repeat, [&] {
      const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(pts, 6, params);
      Poisson function(pts.begin(), pts.end(), PointMap(), NormalMap());
      if (!function.compute_implicit_function()) std::fprintf(stderr, "points_bench: no implicit function\n");
      const Kernel::Sphere_3 bounding = function.bounding_sphere();
      const double radius = 5.0 * std::sqrt(bounding.squared_radius());
      Surface surface(function, Kernel::Sphere_3(function.get_inner_point(), radius * radius),
                      0.375 * spacing / 1000.0 / radius);
      const CGAL::Surface_mesh_default_criteria_3<Triangulation> criteria(20.0, 30.0 * spacing, 0.375 * spacing);
      Triangulation tr;
      Complex c2t3(tr);
      CGAL::make_surface_mesh(c2t3, surface, criteria, CGAL::Manifold_with_boundary_tag());
      SurfaceMesh out;
      if (c2t3.number_of_facets() > 0) CGAL::facets_in_complex_2_to_triangle_mesh(c2t3, out);
    });
    row("poisson_reconstruction", "the mesh's vertex normals, angle 20, radius 30, distance 0.375", name,
        with_normals.size(), t_ours, t_cgal);
  }
  return 0;
}
