// skeleton_mcf: CGAL's mean curvature flow on a torus and a capsule; open
// and non-manifold meshes refused.
#include "skeleton/skeleton_mcf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "skeleton_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::capsule;

TEST(SkeletonMcf, TorusGivesOneLoopAtItsCoreRadius) {
  const double R = 2, r = 0.5;
  const SkeletonMcfResult res = skeleton_mcf(test::torus(R, r, 64, 24));
  const Skeleton& s = res.skeleton;
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("loops"), 1.0);
  EXPECT_EQ(m.at("endpoints"), 0.0);
  EXPECT_EQ(m.at("inside_fraction"), 1.0);
  for (const Vec3& p : s.nodes) {
    EXPECT_NEAR(std::hypot(p.x, p.y), R, 0.02 * R);
    EXPECT_NEAR(p.z, 0.0, 0.02 * R);
  }
  EXPECT_EQ(s.vertex_to_node.size(), test::torus(R, r, 64, 24).positions.size());
}

TEST(SkeletonMcf, CapsuleGivesOneSegmentAlongItsAxis) {
  const double r = 0.5, h = 4;
  const SkeletonMcfResult res = skeleton_mcf(capsule(r, h));
  const Skeleton& s = res.skeleton;
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("endpoints"), 2.0);
  EXPECT_EQ(m.at("junctions"), 0.0);
  EXPECT_EQ(m.at("loops"), 0.0);
  for (const Vec3& p : s.nodes) EXPECT_LT(std::hypot(p.x, p.y), 0.05 * r);
  const BBox box = bounding_box(s);
  EXPECT_GT(box.size().z, h);  // from near one cap's centre to near the other's
}

TEST(SkeletonMcfBadInput, RefusesOpenAndNonManifoldMeshes) {
  try {
    skeleton_mcf(test::grid(4));
    FAIL() << "an open mesh was taken";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("closed"), std::string::npos) << e.what();
  }
  Mesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_THROW(skeleton_mcf(fin), InvalidInput);
}

TEST(SkeletonMcfBadInput, RangesComeFromTheDescription) {
  EXPECT_THROW(skeleton_mcf(test::torus(2, 0.5, 64, 24), {.max_iterations = 0}), InvalidInput);
}

}  // namespace
}  // namespace cgview
