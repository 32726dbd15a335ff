// The measures of a curve skeleton (skeleton/skeleton_measures.h): a
// circle in a torus and its off-centre copy, inside whichever way the faces
// face, spurs pruned.
#include "skeleton/skeleton_measures.h"

#include <gtest/gtest.h>

#include <utility>

#include "io/mesh_io.h"
#include "skeleton/skeleton_projection.h"
#include "skeleton_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::circle;
using test::metrics_json_for_test;

TEST(SkeletonMeasures, CircleInsideATorus) {
  const double R = 2, r = 0.5;
  const Mesh torus = test::torus(R, r, 96, 32);
  const SkeletonMetrics m = measure_skeleton(circle(R, 64), torus);
  EXPECT_EQ(m.loops, 1u);
  EXPECT_EQ(m.endpoints, 0u);
  EXPECT_EQ(m.junctions, 0u);
  EXPECT_EQ(m.branches, 1u);
  EXPECT_DOUBLE_EQ(m.inside_fraction, 1.0);
  EXPECT_EQ(m.centredness_nodes, 64u);
  EXPECT_LT(m.centredness_max, 0.03);
  // Moved outwards by half the tube's radius: centredness 0.5.
  const SkeletonMetrics off = measure_skeleton(circle(R + r / 2, 64), torus);
  EXPECT_NEAR(off.centredness_mean, 0.5, 0.05);
  EXPECT_DOUBLE_EQ(off.inside_fraction, 1.0);
  // Outside the tube altogether.
  EXPECT_DOUBLE_EQ(measure_skeleton(circle(R + 2 * r, 64), torus).inside_fraction, 0.0);
}

// Inside is inside whichever way a closed mesh's faces face: a segment
// through a box counts as inside, and one beside it as outside, with the
// faces turned in as well (CGAL's tetrahedron.off faces in); so does the
// skeleton of that tetrahedron.
TEST(SkeletonMeasures, InsideWhicheverWayTheFacesFace) {
  Mesh box = test::box({0, 0, 0}, {4, 1, 1});
  Skeleton through, beside;
  through.nodes = {{0.5, 0.5, 0.5}, {2, 0.5, 0.5}, {3.5, 0.5, 0.5}};
  through.edges = {{0, 1}, {1, 2}};
  beside = through;
  for (Vec3& n : beside.nodes) n.y += 2;
  for (int turn = 0; turn < 2; ++turn) {
    EXPECT_DOUBLE_EQ(measure_skeleton(through, box).inside_fraction, 1.0) << turn;
    EXPECT_DOUBLE_EQ(measure_skeleton(beside, box).inside_fraction, 0.0) << turn;
    for (Tri& t : box.faces) std::swap(t[1], t[2]);
  }
  const Mesh tetrahedron = read_mesh(test::sample("tetrahedron.off"));
  ASSERT_LT(signed_volume(tetrahedron), 0);
  const Metrics m = skeleton_projection(tetrahedron).metrics;
  EXPECT_EQ(m.at("inside_fraction"), 1.0) << metrics_json_for_test(m);
}

// A body (two legs) and an arm whose hand has three short fingers.
TEST(SkeletonMeasures, PruningSpursKeepsTheLimbs) {
  Skeleton s;
  const auto add = [&](Vec3 p) {
    s.nodes.push_back(p);
    return Index(s.nodes.size() - 1);
  };
  const Index body = add({0, 0, 0}), left = add({-5, -5, 0}), right = add({5, -5, 0});
  const Index elbow = add({0, 5, 0}), hand = add({0, 10, 0});
  s.edges = {{body, left}, {body, right}, {body, elbow}, {elbow, hand}};
  for (double x : {-1.0, 0.0, 1.0}) s.edges.push_back({hand, add({x, 11, 0})});
  EXPECT_EQ(endpoints_after_pruning(s, 0), 5u);  // two legs, three fingers
  EXPECT_EQ(endpoints_after_pruning(s, 2), 3u);  // the fingers go: the arm ends at the hand
  // Legs of 7.07 and fingers go at once; the arm (10) is then a lone path,
  // which has no branch node to be a spur of: it stays, however long.
  EXPECT_EQ(endpoints_after_pruning(s, 7.5), 2u);
  EXPECT_EQ(endpoints_after_pruning(s, 100), 2u);
}
}  // namespace
}  // namespace cgview
