// grid_surface: the boundary of an occupancy grid, of a scalar grid above a
// threshold, and its grid input named through the registry.
#include "voxel/grid_surface.h"

#include <gtest/gtest.h>

#include <string>

#include "algorithm_support.h"
#include "test_support.h"
#include "voxel/voxel_distance.h"
#include "voxel/voxelize.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

TEST(GridSurfaceTest, BoundaryOfAnOccupancyGrid) {
  const VoxelGrid g = voxelize(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16}).grid;
  const GridSurfaceResult r = grid_surface(g);
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  EXPECT_NEAR(test::mesh_volume(r.mesh), 24.0, 1e-9);
  EXPECT_EQ(r.metrics.at("voxels"), 1536);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(GridSurfaceTest, AScalarGridAboveAThreshold) {
  const VoxelGrid depth = voxel_distance(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16}).distance;
  // Deeper than 0.5: more than 2 voxels in from every side, (8-4) x (12-4) x (16-4).
  const GridSurfaceResult r = grid_surface(depth, {.threshold = 0.5});
  EXPECT_EQ(r.metrics.at("voxels"), 4 * 8 * 12);
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  const GridSurfaceResult none = grid_surface(depth, {.threshold = 2});
  EXPECT_EQ(none.mesh.num_faces(), 0u);
  ASSERT_EQ(none.warnings.size(), 1u);
  EXPECT_NE(none.warnings[0].find("no voxel is above the threshold"), std::string::npos);
}

// Its input is the grid named "grid", not a mesh.
TEST(GridSurfaceTest, TakesTheGridInputByName) {
  const VoxelGrid g = voxelize(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16}).grid;
  Inputs in;
  in.add("grid", g);
  EXPECT_EQ(test::artifact<Mesh>(test::run_algorithm("grid_surface", in), "mesh").num_faces(), 12u);
  EXPECT_NE(test::error_of([] { test::run_algorithm("grid_surface", test::box()); }).find("input 'grid' is missing"),
            std::string::npos);
}

}  // namespace
}  // namespace cgview
