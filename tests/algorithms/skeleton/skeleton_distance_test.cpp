// skeleton_distance: two circles a tenth apart, and one against itself.
#include "skeleton/skeleton_distance.h"

#include <gtest/gtest.h>

#include "skeleton_shapes.h"

namespace cgview {
namespace {

using test::circle;

TEST(SkeletonDistance, DistanceBetweenTwoCircles) {
  const Metrics d = skeleton_distance(circle(2.0, 200), circle(2.1, 200)).metrics;
  EXPECT_NEAR(d.at("hausdorff"), 0.1, 0.002);
  EXPECT_NEAR(d.at("mean"), 0.1, 0.002);
  EXPECT_NEAR(skeleton_distance(circle(2.0, 50), circle(2.0, 50)).metrics.at("hausdorff"), 0.0, 1e-12);
}

TEST(SkeletonDistance, ANegativeSpacingIsRefused) {
  EXPECT_THROW(skeleton_distance(circle(2.0, 50), circle(2.0, 50), {.spacing = -1}), InvalidInput);
}

}  // namespace
}  // namespace cgview
