// skeleton_segmentation: each face takes the branch it sees.
#include "skeleton/skeleton_segmentation.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace cgview {
namespace {

TEST(SkeletonSegmentation, EachFaceTakesTheBranchItSees) {
  // Two spheres, each with its own segment inside it.
  const Mesh two = test::merged(test::uv_sphere(1, 16, 32), [] {
    Mesh b = test::uv_sphere(1, 16, 32);
    for (Vec3& p : b.positions) p.x += 5;
    return b;
  }());
  Skeleton s;
  s.nodes = {{0, 0, -0.5}, {0, 0, 0.5}, {5, 0, -0.5}, {5, 0, 0.5}};
  s.edges = {{0, 1}, {2, 3}};
  const SkeletonSegmentationResult res = skeleton_segmentation(two, s);
  const ScalarField& f = res.branch;
  EXPECT_EQ(f.hint, ColorHint::categorical);
  const std::size_t half = two.faces.size() / 2;
  for (std::size_t i = 0; i < two.faces.size(); ++i) ASSERT_EQ(f.values[i], i < half ? f.values[0] : f.values[half]);
  EXPECT_NE(f.values[0], f.values[half]);
}

TEST(SkeletonSegmentationBadInput, ASkeletonWithoutEdgesIsRefused) {
  Skeleton s;
  s.nodes = {{0, 0, 0}};
  EXPECT_THROW(skeleton_segmentation(test::uv_sphere(), s), InvalidInput);
}

}  // namespace
}  // namespace cgview
