// simplify on spheres: down to a face count or a ratio, staying close to the
// input and closed.
#include "filters/simplify.h"

#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <cmath>
#include <string>
#include <string_view>

#include "core/mesh_report.h"
#include "core/surface_mesh.h"
#include "filters/repair.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "repair_first.h"

namespace cgview {
namespace {

TEST(SimplifyTest, SphereToTargetFacesStaysClose) {
  const double r = 1.0;
  const Mesh sphere = test::uv_sphere(r, 64, 128);
  const int target = 500;
  const Mesh out = simplify(sphere, {.target_faces = target}).mesh;
  EXPECT_LE(out.num_faces(), std::size_t(target));
  EXPECT_GT(out.num_faces(), std::size_t(target) * 9 / 10);
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.closed);
  EXPECT_EQ(rep.genus, 0);
  for (const Vec3& p : out.positions) EXPECT_LT(std::abs(norm(p) - r), 0.02 * r);
  const SurfaceMesh a = to_surface_mesh(out).mesh, b = to_surface_mesh(sphere).mesh;
  const double h = CGAL::Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      a, b, CGAL::parameters::number_of_points_per_area_unit(4000),
      CGAL::parameters::number_of_points_per_area_unit(4000));
  EXPECT_LT(h, 0.02 * r);
}

TEST(SimplifyTest, RatioHalvesFaces) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const Mesh out = simplify(sphere, {.ratio = 0.5}).mesh;
  EXPECT_LE(out.num_faces(), sphere.num_faces() / 2);
  EXPECT_TRUE(mesh_report(out).closed);
}

TEST(SimplifyTest, NonManifoldInputIsRefused) {
  const std::string what = test::invalid_input_message([] { simplify(test::non_manifold(), {.repair = false}); });
  EXPECT_NE(what.find("simplify needs a manifold mesh"), std::string::npos) << what;
}

TEST(SimplifyTest, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const SimplifyParams& p) { return simplify(m, p); };
  test::expect_repaired_by_default<SimplifyParams>("simplify", test::sphere_with_a_fin(), run);
  // Two spheres touching at a pole (a bow-tie vertex): the pole is split,
  // each sphere simplified on its own, closed, close to the input.
  const Mesh broken = test::two_spheres_touching();
  const SimplifyResult r = test::expect_repaired_by_default<SimplifyParams>("simplify", broken, run);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("1 vertex duplicated to split non-manifold edges and vertices"), std::string::npos)
      << r.warnings[0];
  const MeshReport rep = mesh_report(r.mesh);
  EXPECT_TRUE(rep.closed);
  EXPECT_EQ(rep.components, 2u);
  EXPECT_LE(r.mesh.num_faces(), broken.num_faces() / 2);
  // Against the repair filter's mesh with repair off: the same mesh, and
  // within 2% of the repaired surface (CGAL's Hausdorff distance).
  const Mesh repaired = repair(broken).mesh;
  test::expect_same_mesh(r.mesh, simplify(repaired, {.repair = false}).mesh);
  const SurfaceMesh a = to_surface_mesh(r.mesh).mesh, b = to_surface_mesh(repaired).mesh;
  const double h = CGAL::Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      a, b, CGAL::parameters::number_of_points_per_area_unit(4000),
      CGAL::parameters::number_of_points_per_area_unit(4000));
  EXPECT_LT(h, 0.02);
  // A manifold mesh is left as it is: no warning.
  EXPECT_TRUE(simplify(test::uv_sphere()).warnings.empty());
}

TEST(SimplifyTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(simplify(test::uv_sphere(1.0, 16, 32), {}, &ctx), Cancelled);
}

TEST(SimplifyTest, ProgressEndsAtOne) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, {});
  simplify(test::uv_sphere(1.0, 16, 32), {.target_faces = 100}, &ctx);
  EXPECT_EQ(last, 1.0);
}

}  // namespace
}  // namespace cgview
