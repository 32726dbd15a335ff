// smooth on a noisy sphere: mean curvature flow pulls it back to round;
// angle smoothing keeps it closed.
#include "filters/smooth.h"

#include <gtest/gtest.h>

#include <string>

#include "core/mesh_report.h"
#include "filters/repair.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "repair_first.h"

namespace cgview {
namespace {

TEST(SmoothTest, MeanCurvatureFlowReducesRadiusVariance) {
  const Mesh noisy = test::noisy_sphere();
  const Mesh out = smooth(noisy, {.method = SmoothMethod::mean_curvature_flow}).mesh;
  EXPECT_EQ(out.num_vertices(), noisy.num_vertices());
  EXPECT_LT(test::radius_variance(out), 0.5 * test::radius_variance(noisy));
}

TEST(SmoothTest, AngleSmoothingKeepsAClosedMesh) {
  const Mesh noisy = test::noisy_sphere();
  const Mesh out = smooth(noisy, {.method = SmoothMethod::angle_and_area, .iterations = 2}).mesh;
  EXPECT_EQ(out.num_vertices(), noisy.num_vertices());
  EXPECT_TRUE(mesh_report(out).closed);
}

TEST(SmoothTest, NonManifoldInputIsRefused) {
  EXPECT_NE(test::invalid_input_message([] {
              smooth(test::non_manifold(), {.repair = false});
            }).find("smooth needs a manifold mesh"),
            std::string::npos);
}

TEST(SmoothTest, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const SmoothParams& p) { return smooth(m, p); };
  test::expect_repaired_by_default<SmoothParams>("smooth", test::sphere_with_a_fin(), run);
  // Two noisy spheres whose poles touch (the upper one's bottom pole is the
  // lower one's top pole): each smoothed on its own, as the repair filter's
  // mesh is with repair off.
  const Mesh noisy = test::noisy_sphere();
  Mesh upper = test::shifted(noisy, noisy.positions.front() - noisy.positions.back());
  upper.positions.back() = noisy.positions.front();
  const Mesh broken = test::welded(test::merged(noisy, upper));
  ASSERT_FALSE(mesh_report(broken).manifold);
  const SmoothResult r = test::expect_repaired_by_default<SmoothParams>("smooth", broken, run);
  EXPECT_EQ(mesh_report(r.mesh).components, 2u);
  test::expect_same_mesh(r.mesh, smooth(repair(broken).mesh, {.repair = false}).mesh);
}

TEST(SmoothTest, RangesComeFromTheDescription) {
  EXPECT_NE(test::invalid_input_message([] {
              smooth(test::uv_sphere(), {.iterations = 0});
            }).find("parameter 'iterations': 0 is under the minimum 1"),
            std::string::npos);
}

TEST(SmoothTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(smooth(test::uv_sphere(1.0, 16, 32), {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
