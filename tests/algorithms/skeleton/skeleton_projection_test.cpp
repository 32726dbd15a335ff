// skeleton_projection: the paper's curve skeleton from projections; the
// medial axis of a rectangle, shapes with known skeletons, the sample
// meshes' loops against CGAL's mean curvature flow, bad view counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "render/renderer.h"
#include "skeleton/skeleton_measures.h"
#include "skeleton/projection/medial_axis.h"
#include "skeleton/projection/thin.h"
#include "skeleton/skeleton_mcf.h"
#include "skeleton/skeleton_projection.h"
#include "voxel/voxel_ops.h"
#include "skeleton_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::capsule;
using test::metrics_json_for_test;

TEST(SkeletonProjection, MedialAxisOfARectangleIsItsMidline) {
  const int w = 40, h = 20;
  std::vector<std::uint8_t> mask(w * h, 0);
  for (int y = 5; y < 15; ++y)
    for (int x = 5; x < 35; ++x) mask[y * w + x] = 1;
  const std::vector<std::uint16_t> dt = skeleton::chamfer_34(mask, w, h);
  EXPECT_EQ(dt[10 * w + 20], 15);  // 5 steps of 3 to the nearest outside pixel
  EXPECT_EQ(dt[5 * w + 20], 3);
  EXPECT_EQ(dt[0], 0);
  const std::vector<std::uint8_t> axis = skeleton::medial_axis(dt, w, h, 2);
  int on = 0;
  for (int x = 12; x < 28; ++x) on += axis[9 * w + x] | axis[10 * w + x];
  EXPECT_EQ(on, 16);  // the midline (rows 9-10) away from the ends
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (axis[y * w + x]) {
        EXPECT_GE(dt[y * w + x], 6);
      }
}

// The paper's method on shapes with known skeletons.
TEST(SkeletonProjection, TorusGivesOneLoopAtItsCoreRadius) {
  const double R = 2, r = 0.5;
  const SkeletonProjectionResult res = skeleton_projection(test::torus(R, r, 64, 24));
  const Skeleton& s = res.skeleton;
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("loops"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("endpoints"), 0.0);
  EXPECT_EQ(m.at("inside_fraction"), 1.0);
  for (const Vec3& p : s.nodes) {
    EXPECT_NEAR(std::hypot(p.x, p.y), R, 0.02 * R);
    EXPECT_NEAR(p.z, 0.0, 0.02 * R);
  }
}

TEST(SkeletonProjection, ABigMeshDrawnDecimatedGivesTheSameSkeleton) {
  // 49k faces drawn whole and drawn as at most 8000 (render_faces): the
  // same loop, at the core radius, within two voxels of the other.
  const double R = 2, r = 0.5;
  const Mesh torus = test::torus(R, r, 256, 96);
  const SkeletonProjectionResult whole = skeleton_projection(torus, {.render_faces = 0});
  const SkeletonProjectionResult decimated = skeleton_projection(torus, {.render_faces = 8000});
  const Skeleton& a = whole.skeleton;
  const Skeleton& b = decimated.skeleton;
  const Metrics& m = decimated.metrics;
  EXPECT_EQ(whole.metrics.at("faces_drawn"), double(torus.faces.size()));
  EXPECT_LE(m.at("faces_drawn"), 8000.0);
  EXPECT_GE(m.at("faces_drawn"), 2000.0);
  EXPECT_EQ(m.at("loops"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("endpoints"), 0.0);
  for (const Vec3& p : b.nodes) {
    EXPECT_NEAR(std::hypot(p.x, p.y), R, 0.02 * R);
    EXPECT_NEAR(p.z, 0.0, 0.02 * R);
  }
  const double voxel = 2 * (R + r) / 128;  // the default grid over the longest side
  EXPECT_LT(measure_distance(a, b).hausdorff, 2 * voxel);
}

TEST(SkeletonProjection, CapsuleGivesOneSegmentAlongItsAxis) {
  const double r = 0.5, h = 4;
  const SkeletonProjectionResult res = skeleton_projection(capsule(r, h));
  const Skeleton& s = res.skeleton;
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("endpoints"), 2.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("junctions"), 0.0);
  EXPECT_EQ(m.at("loops"), 0.0);
  // On the axis to a voxel or two (0.04 here) along the body; the ends, in
  // the caps, to a quarter of the radius.
  for (const Vec3& p : s.nodes) EXPECT_LT(std::hypot(p.x, p.y), (std::abs(p.z) < h / 2 ? 0.1 : 0.25) * r) << p.z;
  EXPECT_GT(bounding_box(s).size().z, 0.8 * h);
}

// Four cylinders (radius 4 voxels, arms 20 long) joined at a centre, as
// voxels, their boundary a closed (T-junctioned) surface: silhouettes need no
// more.
TEST(SkeletonProjection, FourCylindersGiveFourEndsAndOneBranchNode) {
  VoxelGrid g({49, 49, 11}, Vec3{}, 1.0, VoxelType::bit);
  for (int k = 0; k < 11; ++k)
    for (int j = 0; j < 49; ++j)
      for (int i = 0; i < 49; ++i) {
        const double dz = k - 5.0, dx = i - 24.0, dy = j - 24.0;
        if (dx * dx + dz * dz <= 16 || dy * dy + dz * dz <= 16) g.set({i, j, k}, 1);
      }
  const Mesh plus = boundary_mesh(g);
  const SkeletonProjectionResult res = skeleton_projection(plus);
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("endpoints"), 4.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("junctions"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("loops"), 0.0);
  const Skeleton& s = res.skeleton;
  const std::vector<std::uint32_t> degree = node_degrees(s);
  for (std::size_t n = 0; n < s.nodes.size(); ++n)
    if (degree[n] >= 3) {
      EXPECT_NEAR(s.nodes[n].x, 24.5, 2.0);
      EXPECT_NEAR(s.nodes[n].y, 24.5, 2.0);
    }
}

TEST(SkeletonProjection, EveryNodeIsInsideTheSampleMeshes) {
  for (const char* name : {"elephant.off", "armadillo.off", "man.off"}) {
    const Mesh mesh = read_mesh(test::sample(name));
    const SkeletonProjectionResult res = skeleton_projection(mesh);
    const Metrics& m = res.metrics;
    EXPECT_EQ(m.at("inside_fraction"), 1.0) << name << " " << metrics_json_for_test(m);
    EXPECT_EQ(m.at("components"), 1.0) << name;
  }
}

// The same limbs as CGAL's MCF skeleton: MCF gives fingers, toes and bumps a
// short branch each (17-19 ends on man); with spurs under 5% of the diagonal
// pruned from both, MCF's ends are within one of ours, ours has no such spur,
// and each of ours is within 10% of the diagonal of a different one of MCF's.
TEST(SkeletonProjection, ManHasMcfsLimbsOnceSpursArePruned) {
  const Mesh mesh = read_mesh(test::sample("man.off"));
  const BBox box = bounding_box(mesh);
  const double spur = 0.05 * box.diagonal();
  const Skeleton ours = skeleton_projection(mesh).skeleton;
  const Skeleton mcf = skeleton_mcf(mesh).skeleton;
  const std::size_t our_ends = endpoints_after_pruning(ours, spur), mcf_ends = endpoints_after_pruning(mcf, spur);
  EXPECT_EQ(our_ends, 5u);  // head, two hands, two feet
  EXPECT_EQ(our_ends, endpoints_after_pruning(ours, 0));
  EXPECT_LE(std::max(our_ends, mcf_ends) - std::min(our_ends, mcf_ends), 1u) << "MCF: " << mcf_ends;
  EXPECT_GT(endpoints_after_pruning(mcf, 0), mcf_ends + 5);  // MCF's raw count is mostly spurs
  EXPECT_EQ(matched_ends(ends_after_pruning(ours, spur), ends_after_pruning(mcf, spur), 2 * spur), our_ends);
}

// A pipe as long as it is wide: a side view's medial axis runs along its
// middle, and the rays from it cross the hollow between the walls (they
// know only where they enter and leave the pipe); the votes are kept to the
// solid, so every node is inside the walls (before, the skeleton ran along
// the axis, in the hollow), and it goes around the hole once.
TEST(SkeletonProjection, APipesSkeletonStaysInItsWalls) {
  const Mesh pipe = test::swept({{1.0, -1.0}, {1.0, 1.0}, {0.6, 1.0}, {0.6, -1.0}}, 64);
  ASSERT_GT(signed_volume(pipe), 0);
  const SkeletonProjectionResult res = skeleton_projection(pipe);
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("inside_fraction"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("loops"), 1.0) << metrics_json_for_test(m);
  const Skeleton& s = res.skeleton;
  ASSERT_GT(s.nodes.size(), 10u);
  for (const Vec3& n : s.nodes) EXPECT_GT(std::hypot(n.x, n.y), 0.6 - 0.05) << n.x << " " << n.y << " " << n.z;
}

// The centres of a skeleton's independent loops: the cycles that its edges
// outside a breadth-first spanning tree close.
std::vector<Vec3> loop_centres(const Skeleton& s) {
  const Adjacency adj = skeleton_adjacency(s);
  std::vector<std::int64_t> parent(s.nodes.size(), -2), depth(s.nodes.size(), 0);
  for (std::size_t root = 0; root < s.nodes.size(); ++root) {
    if (parent[root] != -2) continue;
    parent[root] = -1;
    std::vector<std::size_t> queue{root};
    for (std::size_t q = 0; q < queue.size(); ++q)
      for (const std::uint32_t* m = adj.begin(queue[q]); m != adj.end(queue[q]); ++m)
        if (parent[*m] == -2) parent[*m] = std::int64_t(queue[q]), depth[*m] = depth[queue[q]] + 1, queue.push_back(*m);
  }
  std::vector<Vec3> centres;
  for (const auto& [a, b] : s.edges) {
    if (parent[a] == std::int64_t(b) || parent[b] == std::int64_t(a)) continue;  // a tree edge
    std::vector<std::size_t> cycle;
    std::size_t x = a, y = b;
    while (x != y) {
      if (depth[x] >= depth[y]) cycle.push_back(x), x = std::size_t(parent[x]);
      else cycle.push_back(y), y = std::size_t(parent[y]);
    }
    cycle.push_back(x);
    Vec3 c{};
    for (std::size_t n : cycle) c += s.nodes[n];
    centres.push_back(c / double(cycle.size()));
  }
  return centres;
}

// Loops are the shape's tunnels: as many as the genus on sample meshes with
// one to four tunnels wider than a few voxels (tori, a knot, a gear, an
// anchor), none for the man (genus 0); on the elephant (genus 3), each loop goes
// around one of the tunnels that CGAL's mean-curvature-flow skeleton goes
// around (its loops' centres, within 6% of the diagonal), a different one
// each, all three, and so on the same elephant four times finer.
TEST(SkeletonProjection, LoopsAreTheShapesTunnels) {
  for (const auto& [name, genus] : std::vector<std::pair<const char*, double>>{{"eight.off", 2},
                                                                               {"man.off", 0},
                                                                               {"knot.off", 1},
                                                                               {"torus_quad.off", 1},
                                                                               {"pinion.off", 1},
                                                                               {"double-torus-example.off", 2},
                                                                               {"3torus.off", 3},
                                                                               {"anchor.off", 4}}) {
    const Mesh mesh = read_mesh(test::sample(name));
    ASSERT_EQ(double(mesh_report(mesh).genus.value_or(-1)), genus) << name;
    const SkeletonProjectionResult res = skeleton_projection(mesh);
    const Metrics& m = res.metrics;
    EXPECT_EQ(m.at("loops"), genus) << name << " " << metrics_json_for_test(m);
    EXPECT_EQ(m.at("inside_fraction"), 1.0) << name;
    EXPECT_EQ(m.at("components"), 1.0) << name;
  }
  const Mesh elephant = read_mesh(test::sample("elephant.off"));
  const std::vector<Vec3> mcf = loop_centres(skeleton_mcf(elephant).skeleton);
  ASSERT_EQ(mcf.size(), 3u);
  const double near = 0.06 * bounding_box(elephant).diagonal();
  for (const char* name : {"elephant.off", "refined_elephant.off"}) {
    const SkeletonProjectionResult res =
        skeleton_projection(name == std::string("elephant.off") ? elephant : read_mesh(test::sample(name)));
    const std::vector<Vec3> ours = loop_centres(res.skeleton);
    EXPECT_EQ(ours.size(), 3u) << name;
    std::vector<bool> taken(mcf.size(), false);
    for (const Vec3& c : ours) {
      std::size_t best = 0;
      for (std::size_t k = 1; k < mcf.size(); ++k)
        if (norm(mcf[k] - c) < norm(mcf[best] - c)) best = k;
      EXPECT_LT(norm(mcf[best] - c), near)
          << name << ": a loop around (" << c.x << ", " << c.y << ", " << c.z << ") is no tunnel of MCF's";
      EXPECT_FALSE(taken[best]) << name << ": two loops around the tunnel at (" << mcf[best].x << ", " << mcf[best].y
                                << ", " << mcf[best].z << ")";
      taken[best] = true;
    }
    const Metrics& m = res.metrics;
    EXPECT_EQ(m.at("inside_fraction"), 1.0) << name;
    EXPECT_EQ(m.at("components"), 1.0) << name;
  }
}

// The thinning leaves out the weakest votes (under a fifth of the targets')
// unless that splits the targets: two strongly voted bars joined only by a
// bridge of 3% of the most votes give one skeleton from end to end.
TEST(SkeletonProjection, PartsJoinedOnlyByWeakVotesStayJoined) {
  VoxelGrid votes({60, 12, 12}, Vec3{0, 0, 0}, 1.0, VoxelType::float32);
  std::vector<float>& v = votes.floats();
  for (int x = 5; x < 55; ++x)
    for (int y = 5; y < 8; ++y)
      for (int z = 5; z < 8; ++z) v[votes.linear({x, y, z})] = x >= 26 && x < 34 ? 3.f : 100.f;
  const std::vector<float> radius(votes.size(), 1.5f);
  const Skeleton s = skeleton::thin(votes, radius, SkeletonProjectionParams{});
  std::vector<std::uint32_t> component;
  EXPECT_EQ(skeleton_components(s, component), 1u);
  double lo = 1e9, hi = -1e9;
  for (const Vec3& n : s.nodes) lo = std::min(lo, n.x), hi = std::max(hi, n.x);
  EXPECT_LT(lo, 10);
  EXPECT_GT(hi, 50);
}

// Contexts left to the algorithm (0) are 1 on a GPU, where more only add
// copies of the mesh, and 2 on llvmpipe; how many draw changes no view.
TEST(SkeletonProjection, RenderContextsChangeTheTimeAlone) {
  const Mesh mesh = capsule(0.5, 4);
  const SkeletonProjectionResult automatic = skeleton_projection(mesh);
  const SkeletonProjectionResult three = skeleton_projection(mesh, {.contexts = 3});
  const render::Renderer renderer;
  EXPECT_EQ(automatic.metrics.at("render_contexts"), renderer.info().software ? 2.0 : 1.0);
  EXPECT_EQ(three.metrics.at("render_contexts"), 3.0);
  ASSERT_EQ(automatic.skeleton.nodes.size(), three.skeleton.nodes.size());
  EXPECT_LT(measure_distance(automatic.skeleton, three.skeleton).hausdorff, 1e-9);  // summation order only
}

// A long stage reports as it goes (issue 38): at 200 views (100 drawings,
// on two contexts on llvmpipe) the silhouettes report many increasing
// fractions before the votes start, the votes and the thinning report
// theirs, and every report names its stage; the fractions never go back.
TEST(SkeletonProjection, StagesReportProgressAsTheyGo) {
  std::vector<std::pair<double, std::string>> reports;
  Context ctx([&](double f, std::string_view stage) { reports.emplace_back(f, std::string(stage)); }, nullptr);
  const SkeletonProjectionResult res = skeleton_projection(test::torus(2, 0.5, 64, 24), {.views = 200}, &ctx);
  EXPECT_EQ(res.metrics.at("loops"), 1.0);
  ASSERT_FALSE(reports.empty());
  EXPECT_EQ(reports.back(), (std::pair<double, std::string>{1.0, "done"}));
  std::map<std::string, std::vector<double>> by_stage;
  std::vector<std::string> order;  // the stages in the order they first report
  for (std::size_t i = 0; i < reports.size(); ++i) {
    const auto& [f, stage] = reports[i];
    EXPECT_FALSE(stage.empty()) << "report " << i;
    if (i > 0) {
      EXPECT_GE(f, reports[i - 1].first) << "report " << i << " (" << stage << ") goes back";
    }
    if (!by_stage.count(stage)) order.push_back(stage);
    by_stage[stage].push_back(f);
  }
  const std::vector<std::string> expected = {"rendering silhouettes",
                                             "medial axes and votes",
                                             "keeping votes inside the solid",
                                             "thinning",
                                             "closing loops",
                                             "merging and smoothing",
                                             "moving nodes inside",
                                             "done"};
  EXPECT_EQ(order, expected);
  // Each stage's reports come together: no stage reports again after the next began.
  std::size_t runs = 1;
  for (std::size_t i = 1; i < reports.size(); ++i) runs += reports[i].second != reports[i - 1].second;
  EXPECT_EQ(runs, expected.size());
  auto distinct_within = [&](const std::string& stage, double lo, double hi) {
    std::set<double> in;
    for (double f : by_stage[stage]) {
      EXPECT_GE(f, lo) << stage;
      EXPECT_LE(f, hi) << stage;
      in.insert(f);
    }
    return in.size();
  };
  EXPECT_GE(distinct_within("rendering silhouettes", 0.0, 0.4), 20u);
  EXPECT_GE(distinct_within("medial axes and votes", 0.4, 0.75), 5u);
  EXPECT_GE(distinct_within("thinning", 0.8, 0.95), 3u);
  EXPECT_GE(distinct_within("closing loops", 0.8, 0.95), 2u);
}

// Cancelled while the silhouettes are drawn: the capture stops there (no
// vote is counted), and the next run draws as before.
TEST(SkeletonProjection, CancelledWhileDrawingStopsBeforeTheVotes) {
  const Mesh torus = test::torus(2, 0.5, 64, 24);
  std::atomic<bool> cancel = false;
  std::vector<std::string> stages;
  Context ctx(
      [&](double f, std::string_view stage) {
        stages.emplace_back(stage);
        if (stage == "rendering silhouettes" && f > 0.1) cancel = true;
      },
      [&] { return cancel.load(); });
  EXPECT_THROW(skeleton_projection(torus, {.views = 200}, &ctx), Cancelled);
  EXPECT_TRUE(cancel);
  EXPECT_EQ(std::count(stages.begin(), stages.end(), "medial axes and votes"), 0);
  EXPECT_EQ(skeleton_projection(torus).metrics.at("loops"), 1.0);
}

TEST(SkeletonProjection, BadViewCounts) {
  const Mesh sphere = test::uv_sphere();
  for (long long views : {0LL, 3LL, 2000LL}) {
    try {
      skeleton_projection(sphere, {.views = int(views)});
      FAIL() << views << " views were taken";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("views"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace cgview
