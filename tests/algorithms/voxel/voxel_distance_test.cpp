// voxel_distance: the depth inside a box, and a memory limit that counts
// the distances.
#include "voxel/voxel_distance.h"

#include <gtest/gtest.h>

#include <string>

#include "test_support.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

TEST(VoxelDistanceTest, GivesAScalarGrid) {
  const VoxelDistanceResult r = voxel_distance(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16});
  EXPECT_EQ(r.distance.type(), VoxelType::float32);
  EXPECT_FLOAT_EQ(r.distance.get({4, 7, 9}), 1.0f);
  EXPECT_FLOAT_EQ(float(r.metrics.at("max_distance")), 1.0f);
  // Its memory limit counts the distances too.
  EXPECT_NE(test::error_of([] { voxel_distance(test::box(), {.resolution = 1000}); }).find("13 bytes per voxel"),
            std::string::npos);
}

// 1 MB for voxel_distance leaves 1/13 MB to the grid, under voxelize's own
// minimum: a small grid still fits.
TEST(VoxelDistanceTest, ASmallLimitStillTakesASmallGrid) {
  const VoxelDistanceResult r = voxel_distance(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16, .max_memory_mb = 1});
  EXPECT_EQ(r.metrics.at("voxels"), 1536);
}

}  // namespace
}  // namespace cgview
