// voxel_surface: the merged boundary of a box's voxels is the box.
#include "voxel/voxel_surface.h"

#include <gtest/gtest.h>

#include "test_support.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

TEST(VoxelSurfaceTest, GivesTheMergedBoundary) {
  const VoxelSurfaceResult r = voxel_surface(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16});
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  EXPECT_NEAR(test::mesh_volume(r.mesh), 24.0, 1e-9);
  EXPECT_EQ(r.metrics.at("voxels"), 1536);
}

TEST(VoxelSurfaceTest, RangesComeFromTheDescription) {
  EXPECT_NE(test::error_of([] {
              voxel_surface(test::box(), {.resolution = 0});
            }).find("parameter 'resolution': 0 is under the minimum 1"),
            std::string::npos);
}

}  // namespace
}  // namespace cgview
