// The grid operations (voxel/voxel_ops.h): simple points, the Euclidean
// distance transform, thresholds, the merged boundary mesh, slices.
#include "voxel/voxel_ops.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "test_support.h"
#include "voxel/voxelize.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

using test::error_of;
using test::mesh_volume;
using test::vox;

TEST(VoxelOpsTest, SimplePoints) {
  VoxelGrid g({7, 7, 7}, {0, 0, 0}, 1.0);
  g.set({3, 3, 3}, 1);
  EXPECT_FALSE(is_simple(g, {3, 3, 3}));  // isolated: removing it deletes a component
  g.set({4, 3, 3}, 1);
  g.set({5, 3, 3}, 1);
  EXPECT_TRUE(is_simple(g, {3, 3, 3}));   // end of a line
  EXPECT_FALSE(is_simple(g, {4, 3, 3}));  // middle: removing it splits the line
  EXPECT_FALSE(is_simple(g, {0, 0, 0}));  // empty
  VoxelGrid cube({5, 5, 5}, {0, 0, 0}, 1.0);
  for (int k = 1; k < 4; ++k)
    for (int j = 1; j < 4; ++j)
      for (int i = 1; i < 4; ++i) cube.set({i, j, k}, 1);
  EXPECT_FALSE(is_simple(cube, {2, 2, 2}));  // centre: removing it makes a cavity
  EXPECT_TRUE(is_simple(cube, {1, 1, 1}));   // corner
  EXPECT_TRUE(is_simple(cube, {2, 1, 1}));   // edge
  EXPECT_TRUE(is_simple(cube, {2, 2, 1}));   // face
  // A ring of 8 voxels around a hole: removing any one opens the tunnel.
  VoxelGrid ring({5, 5, 3}, {0, 0, 0}, 1.0);
  for (int j = 1; j < 4; ++j)
    for (int i = 1; i < 4; ++i)
      if (i != 2 || j != 2) ring.set({i, j, 1}, 1);
  EXPECT_FALSE(is_simple(ring, {2, 1, 1}));
  // A corner: its two neighbours on the ring touch by an edge, 26-adjacent, so the ring stays closed.
  EXPECT_TRUE(is_simple(ring, {1, 1, 1}));
}

TEST(VoxelOpsTest, DistanceTransformIsEuclidean) {
  VoxelGrid g({20, 20, 20}, {0, 0, 0}, 0.5);
  g.set({2, 3, 4}, 1);
  const VoxelGrid d = distance_transform(g, {.inside = false});
  EXPECT_EQ(d.type(), VoxelType::float32);
  EXPECT_FLOAT_EQ(d.get({2, 3, 4}), 0.f);
  EXPECT_FLOAT_EQ(d.get({5, 7, 4}), 2.5f);  // (3, 4, 0) voxels: 5 * 0.5
  EXPECT_FLOAT_EQ(d.get({19, 19, 19}), float(0.5 * std::sqrt(17.0 * 17 + 16 * 16 + 15 * 15)));
  // Inside a solid box: the distance to the nearest empty voxel.
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const VoxelGrid in = distance_transform(box.grid);
  EXPECT_FLOAT_EQ(in.get({0, 0, 0}), 0.f);
  EXPECT_FLOAT_EQ(in.get({1, 1, 1}), 0.25f);
  EXPECT_FLOAT_EQ(in.get({4, 7, 9}), 1.0f);  // 4 voxels from the x = 0 side
  // Brute force on a small random grid.
  VoxelGrid rnd({9, 8, 7}, {0, 0, 0}, 1.0);
  std::mt19937 rng(3);
  for (auto& b : rnd.bytes()) b = rng() % 5 == 0;
  const VoxelGrid dr = distance_transform(rnd, {.inside = false});
  for (std::size_t n = 0; n < rnd.size(); ++n) {
    double best = HUGE_VAL;
    const VoxelIndex v = rnd.unlinear(n);
    for (std::size_t m = 0; m < rnd.size(); ++m)
      if (rnd.bytes()[m]) {
        const VoxelIndex w = rnd.unlinear(m);
        best = std::min(
            best, std::sqrt(double((v.i - w.i) * (v.i - w.i) + (v.j - w.j) * (v.j - w.j) + (v.k - w.k) * (v.k - w.k))));
      }
    ASSERT_FLOAT_EQ(dr.floats()[n], float(best)) << n;
  }
}

TEST(VoxelOpsTest, ScalarGridThresholds) {
  // The distance inside a solid box, thresholded: the voxels deeper than 0.5.
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const VoxelGrid depth = distance_transform(box.grid);
  const auto [lo, hi] = value_range(depth);
  EXPECT_EQ(lo, 0.f);
  EXPECT_FLOAT_EQ(hi, 1.0f);  // half the shortest side
  const VoxelGrid deep = threshold(depth, 0.5f);
  EXPECT_EQ(deep.type(), VoxelType::bit);
  // Depth d > 0.5 means more than 2 voxels in from every side: (8-4) x (12-4) x (16-4).
  EXPECT_EQ(deep.count_occupied(), 4u * 8u * 12u);
  EXPECT_EQ(threshold(depth, hi).count_occupied(), 0u);
  EXPECT_EQ(threshold(depth, -1.f).count_occupied(), depth.size());
}

TEST(VoxelOpsTest, BoundaryMeshMergesCoplanarFaces) {
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const Mesh m = boundary_mesh(box.grid);
  EXPECT_EQ(m.num_faces(), 12u);  // six rectangles
  EXPECT_EQ(m.num_vertices(), 8u);
  EXPECT_NEAR(mesh_volume(m), 24.0, 1e-9);  // outward: positive
  const VoxelizeResult sphere = vox(test::uv_sphere(1.0, 32, 64), 32, VoxelizeMode::solid);
  const Mesh ms = boundary_mesh(sphere.grid);
  const double s = sphere.grid.voxel_size();
  EXPECT_NEAR(mesh_volume(ms), double(sphere.solid_voxels) * s * s * s, 1e-9);
  // Merged: far fewer triangles than the 2 per exposed voxel face.
  std::size_t exposed = 0;
  for (std::size_t n = 0; n < sphere.grid.size(); ++n) {
    const VoxelIndex v = sphere.grid.unlinear(n);
    if (!sphere.grid.occupied(v)) continue;
    for (const VoxelIndex& o : VoxelGrid::offsets(Connectivity::six))
      exposed += !sphere.grid.occupied({v.i + o.i, v.j + o.j, v.k + o.k});
  }
  EXPECT_LT(ms.num_faces(), exposed);
}

TEST(VoxelOpsTest, SliceIndicesAreChecked) {
  const VoxelizeResult r = vox(test::box(), 8, VoxelizeMode::solid);
  EXPECT_NE(error_of([&] {
              slice(r.grid, 2, 10);
            }).find("slice index 10 is out of range: the grid has 10 voxels along z (0..9)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { slice(r.grid, 2, -1); }).find("out of range"), std::string::npos);
  EXPECT_NE(error_of([&] { slice(r.grid, 3, 0); }).find("axis"), std::string::npos);
}

}  // namespace
}  // namespace cgview
