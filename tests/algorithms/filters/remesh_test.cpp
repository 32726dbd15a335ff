// remesh on spheres: the edges reach the target length (by default the
// input's mean) and the mesh stays closed.
#include "filters/remesh.h"

#include <gtest/gtest.h>

#include <string>

#include "core/mesh_report.h"
#include "filters/repair.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "repair_first.h"

namespace cgview {
namespace {

TEST(RemeshTest, ReachesTargetEdgeLength) {
  const Mesh sphere = test::uv_sphere(1.0, 24, 48);
  const double target = 0.1;
  const Mesh out = remesh(sphere, {.target_edge_length = target, .iterations = 3}).mesh;
  EXPECT_NEAR(test::mean_edge_length(out), target, 0.2 * target);
  EXPECT_TRUE(mesh_report(out).closed);
}

TEST(RemeshTest, ZeroMeansInputMeanEdgeLength) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const double before = test::mean_edge_length(sphere);
  const Mesh out = remesh(sphere).mesh;
  EXPECT_NEAR(test::mean_edge_length(out), before, 0.2 * before);
}

TEST(RemeshTest, NonManifoldInputIsRefused) {
  const std::string what = test::invalid_input_message([] { remesh(test::non_manifold(), {.repair = false}); });
  EXPECT_NE(what.find("remesh needs a manifold mesh"), std::string::npos) << what;
}

TEST(RemeshTest, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const RemeshParams& p) { return remesh(m, p); };
  test::expect_repaired_by_default<RemeshParams>("remesh", test::sphere_with_a_fin(), run);
  // Two boxes on one edge: two closed boxes, as the repair filter's mesh
  // remeshed with repair off.
  const Mesh broken = test::two_boxes_sharing_an_edge();
  const RemeshResult r = test::expect_repaired_by_default<RemeshParams>("remesh", broken, run);
  const MeshReport rep = mesh_report(r.mesh);
  EXPECT_TRUE(rep.closed);
  EXPECT_EQ(rep.components, 2u);
  test::expect_same_mesh(r.mesh, remesh(repair(broken).mesh, {.repair = false}).mesh);
}

TEST(RemeshTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(remesh(test::uv_sphere(1.0, 16, 32), {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
