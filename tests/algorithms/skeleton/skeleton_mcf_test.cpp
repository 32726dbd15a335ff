// skeleton_mcf: CGAL's mean curvature flow on a torus and a capsule; open
// and non-manifold meshes refused.
#include "skeleton/skeleton_mcf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "filters/repair.h"
#include "skeleton/skeleton_measures.h"
#include "non_manifold_shapes.h"
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
  try {
    skeleton_mcf(fin, {.repair = false});
    FAIL() << "a non-manifold mesh was taken with repair off";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("skeleton_mcf needs a manifold mesh"), std::string::npos) << e.what();
  }
  // Repaired by default, the fin is still open: refused for that.
  try {
    skeleton_mcf(fin);
    FAIL() << "an open mesh was taken";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("closed mesh: this one has borders once repaired"), std::string::npos)
        << e.what();
  }
}

// Two capsules end to end, their poles one vertex: by default a repaired
// copy is contracted, two segments along the axis, each vertex of the
// input given a node of its own capsule; as CGAL's skeleton of the repair
// filter's mesh with repair off.
TEST(SkeletonMcf, NonManifoldMeshIsRepairedFirstByDefault) {
  EXPECT_TRUE(SkeletonMcfParams{}.repair);
  const double r = 0.5, h = 4, top = h / 2 + r;
  const Mesh one = capsule(r, h);
  const Mesh broken = test::welded(test::merged(one, test::shifted(one, {0, 0, 2 * top})));
  ASSERT_EQ(broken.num_vertices(), 2 * one.num_vertices() - 1);
  const Mesh before = broken;
  const SkeletonMcfResult res = skeleton_mcf(broken);
  test::expect_same_mesh(broken, before);
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_EQ(res.warnings[0].rfind("skeleton_mcf: the mesh was not manifold", 0), 0u) << res.warnings[0];
  EXPECT_NE(res.warnings[0].find("a copy was repaired first: 1 vertex duplicated"), std::string::npos)
      << res.warnings[0];
  const Skeleton& s = res.skeleton;
  EXPECT_EQ(res.metrics.at("endpoints"), 4.0);
  EXPECT_EQ(res.metrics.at("junctions"), 0.0);
  EXPECT_EQ(res.metrics.at("loops"), 0.0);
  // On the axis (less closely than one capsule's: the medial pull near
  // the pole they share sees both).
  for (const Vec3& p : s.nodes) EXPECT_LT(std::hypot(p.x, p.y), 0.25 * r);
  ASSERT_EQ(s.vertex_to_node.size(), broken.num_vertices());
  for (std::size_t v = 0; v < broken.num_vertices(); ++v) {
    const double z = broken.positions[v].z;
    if (z != top) {
      EXPECT_EQ(s.nodes[s.vertex_to_node[v]].z > top, z > top) << "vertex " << v;
    }
  }
  // CGAL's skeleton of the repair filter's mesh, with repair off: the same
  // shape (not node for node: the flow's remeshing differs from run to run
  // by up to a third of the radius at the ends).
  const SkeletonMcfResult ref = skeleton_mcf(repair(broken).mesh, {.repair = false});
  for (const char* m : {"endpoints", "junctions", "loops"}) EXPECT_EQ(res.metrics.at(m), ref.metrics.at(m)) << m;
  EXPECT_LT(measure_distance(s, ref.skeleton).hausdorff, 0.5 * r);
  try {
    skeleton_mcf(broken, {.repair = false});
    FAIL() << "a non-manifold mesh was taken with repair off";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("skeleton_mcf needs a manifold mesh"), std::string::npos) << e.what();
  }
}

TEST(SkeletonMcfBadInput, RangesComeFromTheDescription) {
  EXPECT_THROW(skeleton_mcf(test::torus(2, 0.5, 64, 24), {.max_iterations = 0}), InvalidInput);
}

}  // namespace
}  // namespace cgview
