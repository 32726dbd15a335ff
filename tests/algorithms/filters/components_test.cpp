// components: two boxes counted, the largest kept, the small one dropped.
#include "filters/components.h"

#include <gtest/gtest.h>

#include <string>

#include "filter_shapes.h"
#include "invalid_input.h"
#include "repair_first.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(Components, CountKeepLargestAndDropSmall) {
  const Mesh two = test::merged(test::box(), test::box({2, 0, 0}, {3, 1, 1}));
  const ComponentsResult counted = components(two, {.mode = ComponentsMode::count});
  EXPECT_EQ(counted.metrics.at("components"), 2.0);
  EXPECT_EQ(counted.metrics.at("kept"), 2.0);
  EXPECT_EQ(counted.mesh.num_faces(), 24u);

  const ComponentsResult largest = components(two);
  EXPECT_EQ(largest.metrics.at("kept"), 1.0);
  EXPECT_EQ(largest.mesh.num_faces(), 12u);
  EXPECT_EQ(largest.mesh.num_vertices(), 8u);

  const Mesh uneven = test::merged(test::box(), subdivide_midpoint(test::box({2, 0, 0}, {3, 1, 1})));
  const ComponentsResult dropped = components(uneven, {.mode = ComponentsMode::drop_smaller_than, .min_faces = 20});
  EXPECT_EQ(dropped.metrics.at("kept"), 1.0);
  const Mesh& kept = dropped.mesh;
  EXPECT_EQ(kept.num_faces(), 48u);
  for (const Vec3& p : kept.positions) EXPECT_GE(p.x, 2.0);
}

TEST(Components, NonManifoldIsRefused) {
  EXPECT_NE(test::invalid_input_message([] { components(test::non_manifold(), {.repair = false}); }).find("manifold"),
            std::string::npos);
}

TEST(Components, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const ComponentsParams& p) { return components(m, p); };
  test::expect_repaired_by_default<ComponentsParams>("components", test::sphere_with_a_fin(), run);
  // Two boxes on one edge are two components once the edge is split.
  const ComponentsResult r =
      test::expect_repaired_by_default<ComponentsParams>("components", test::two_boxes_sharing_an_edge(), run);
  EXPECT_EQ(r.metrics.at("components"), 2.0);
  EXPECT_EQ(r.metrics.at("kept"), 1.0);
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  EXPECT_TRUE(mesh_report(r.mesh).closed);
}

TEST(Components, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  components(test::box(), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(components(test::box(), {}, &cancelled), Cancelled);
}

TEST(Components, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("components").info.area, "filters"); }

}  // namespace
}  // namespace cgview
