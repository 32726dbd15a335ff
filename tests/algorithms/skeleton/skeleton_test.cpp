// Curve skeletons: every file format round-trips and bad files name their
// line; the measures of analytic skeletons (a circle in a torus, its
// off-centre copy); CGAL's mean curvature flow on a torus and a capsule;
// segmentation by branches; bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "algorithm_support.h"
#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "skeleton/skeleton_metrics.h"
#include "skeleton/skeleton_projection.h"
#include "voxel/voxel_ops.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::artifact;
using test::run_algorithm;

std::string metrics_json_for_test(const Metrics& m) {
  std::string out;
  for (const auto& [k, v] : m) out += k + "=" + std::to_string(v) + " ";
  return out;
}

// A circle of n nodes, radius R, in the z = 0 plane, around (0, 0, 0).
Skeleton circle(double R, int n) {
  Skeleton s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    s.nodes.push_back({R * std::cos(a), R * std::sin(a), 0});
    s.edges.push_back({Index(i), Index((i + 1) % n)});
  }
  return s;
}

// A capsule along z: radius r, cylinder from -h/2 to h/2, hemispherical ends.
Mesh capsule(double r, double h) {
  std::vector<std::pair<double, double>> profile;
  const int cap = 12, body = 40;
  for (int i = 0; i <= cap; ++i) {
    const double t = std::numbers::pi / 2 * i / cap;
    profile.push_back({r * std::sin(t), h / 2 + r * std::cos(t)});
  }
  for (int i = 1; i < body; ++i) profile.push_back({r, h / 2 - h * i / body});
  for (int i = 0; i <= cap; ++i) {
    const double t = std::numbers::pi / 2 * i / cap;
    profile.push_back({r * std::cos(t), -h / 2 - r * std::sin(t)});
  }
  return test::revolve(profile, 32);
}

Skeleton sample_skeleton() {
  Skeleton s;  // a Y: three branches meeting at node 1, one with a middle node
  s.nodes = {{0, 0, 0}, {0, 1, 0}, {-1, 2, 0.5}, {1, 2, -0.25}, {1.5, 3, 0.125}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  return s;
}

TEST(SkeletonFiles, EveryFormatRoundTrips) {
  const Skeleton s = sample_skeleton();
  for (const char* name : {"y.polylines.txt", "y.cg", "y.obj", "y.json"}) {
    const SkeletonFormat f = skeleton_format_from_name(name);
    const Skeleton back = read_skeleton_bytes(write_skeleton_bytes(s, f), f, name);
    ASSERT_EQ(back.nodes.size(), s.nodes.size()) << name;
    ASSERT_EQ(back.edges.size(), s.edges.size()) << name;
    // Same nodes (polylines may renumber them) and the same edges between them.
    const SkeletonMetrics a = skeleton_shape_metrics(s), b = skeleton_shape_metrics(back);
    EXPECT_EQ(a.endpoints, b.endpoints) << name;
    EXPECT_EQ(a.junctions, b.junctions) << name;
    EXPECT_DOUBLE_EQ(a.length, b.length) << name;
    EXPECT_NEAR(skeleton_distance(s, back).hausdorff, 0.0, 1e-12) << name;
  }
}

TEST(SkeletonFiles, ReadsWhatOtherToolsWrite) {
  // CGAL's polylines: branches share their end points exactly.
  const Skeleton p =
      read_skeleton_bytes("3 0 0 0 0 1 0 0 2 0\n2 0 1 0 1 1 0\n", SkeletonFormat::polylines, "cgal.polylines.txt");
  EXPECT_EQ(p.nodes.size(), 4u);
  EXPECT_EQ(p.edges.size(), 3u);
  // The .cg curve graph of the contraction tools.
  const Skeleton c =
      read_skeleton_bytes("# D:3 NV:3 NE:2\nv 0 0 0\nv 1 0 0\nv 2 0 0\ne 1 2\ne 2 3\n", SkeletonFormat::cg, "a.cg");
  EXPECT_EQ(c.edges.size(), 2u);
  EXPECT_EQ(c.edges[1][1], 2u);
  // OBJ polylines with negative indices, other records ignored.
  const Skeleton o =
      read_skeleton_bytes("o s\nv 0 0 0\nv 1 0 0\nv 2 0 0\nl 1 2 -1\nvn 0 0 1\n", SkeletonFormat::obj, "a.obj");
  EXPECT_EQ(o.edges.size(), 2u);
}

TEST(SkeletonFiles, BadFilesNameTheLine) {
  const auto line_of = [](const std::string& bytes, SkeletonFormat f) -> std::optional<std::uint64_t> {
    try {
      read_skeleton_bytes(bytes, f, "bad");
    } catch (const ParseError& e) {
      return e.line();
    }
    return std::nullopt;
  };
  EXPECT_EQ(line_of("# D:3\nv 0 0 0\nv 1 0 0\ne 1 3\n", SkeletonFormat::cg), 4u);     // index out of range
  EXPECT_EQ(line_of("v 0 0 0\nv 1 x 0\n", SkeletonFormat::cg), 2u);                   // not a number
  EXPECT_EQ(line_of("v 0 0 0\nv 1 0 0\ne 1 1\n", SkeletonFormat::cg), 3u);            // a loop edge
  EXPECT_EQ(line_of("v 0 0 0\nf 1 2 3\n", SkeletonFormat::cg), 2u);                   // unknown record
  EXPECT_EQ(line_of("2 0 0 0 1 1 1\n3 0 0 0 1 1\n", SkeletonFormat::polylines), 2u);  // short polyline
  EXPECT_EQ(line_of("v 0 0 0\nl 1 7\n", SkeletonFormat::obj), 2u);
  EXPECT_EQ(line_of("{\"nodes\": [[0, 0, 0]],\n \"edges\": [[0, 1]\n", SkeletonFormat::json), 3u);  // not JSON
  EXPECT_THROW(read_skeleton_bytes("{\"nodes\": [[0, 0, 0]], \"edges\": [[0, 4]]}", SkeletonFormat::json, "j"),
               ParseError);
  EXPECT_THROW(read_skeleton_bytes("", SkeletonFormat::cg, "empty"), ParseError);
  // A number past a double: nlohmann's out_of_range escaped as another
  // exception (tests/fuzz/corpus/skeleton/regression-number-overflow).
  EXPECT_THROW(read_skeleton_bytes("362006e8618", SkeletonFormat::json, "big"), ParseError);
  EXPECT_THROW(read_skeleton_bytes("{\"nodes\": [[0, 0, 1e999]], \"edges\": []}", SkeletonFormat::json, "big"),
               ParseError);
  EXPECT_THROW(skeleton_format_from_name("a.stl"), UnsupportedFormat);
}

TEST(SkeletonMetrics, CircleInsideATorus) {
  const double R = 2, r = 0.5;
  const Mesh torus = test::torus(R, r, 96, 32);
  const SkeletonMetrics m = skeleton_metrics(circle(R, 64), torus);
  EXPECT_EQ(m.loops, 1u);
  EXPECT_EQ(m.endpoints, 0u);
  EXPECT_EQ(m.junctions, 0u);
  EXPECT_EQ(m.branches, 1u);
  EXPECT_DOUBLE_EQ(m.inside_fraction, 1.0);
  EXPECT_EQ(m.centredness_nodes, 64u);
  EXPECT_LT(m.centredness_max, 0.03);
  // Moved outwards by half the tube's radius: centredness 0.5.
  const SkeletonMetrics off = skeleton_metrics(circle(R + r / 2, 64), torus);
  EXPECT_NEAR(off.centredness_mean, 0.5, 0.05);
  EXPECT_DOUBLE_EQ(off.inside_fraction, 1.0);
  // Outside the tube altogether.
  EXPECT_DOUBLE_EQ(skeleton_metrics(circle(R + 2 * r, 64), torus).inside_fraction, 0.0);
}

// Inside is inside whichever way a closed mesh's faces face: a segment
// through a box counts as inside, and one beside it as outside, with the
// faces turned in as well (CGAL's tetrahedron.off faces in); so does the
// skeleton of that tetrahedron.
TEST(SkeletonMetrics, InsideWhicheverWayTheFacesFace) {
  Mesh box = test::box({0, 0, 0}, {4, 1, 1});
  Skeleton through, beside;
  through.nodes = {{0.5, 0.5, 0.5}, {2, 0.5, 0.5}, {3.5, 0.5, 0.5}};
  through.edges = {{0, 1}, {1, 2}};
  beside = through;
  for (Vec3& n : beside.nodes) n.y += 2;
  for (int turn = 0; turn < 2; ++turn) {
    EXPECT_DOUBLE_EQ(skeleton_metrics(through, box).inside_fraction, 1.0) << turn;
    EXPECT_DOUBLE_EQ(skeleton_metrics(beside, box).inside_fraction, 0.0) << turn;
    for (Tri& t : box.faces) std::swap(t[1], t[2]);
  }
  const Mesh tetrahedron = read_mesh(test::sample("tetrahedron.off"));
  ASSERT_LT(signed_volume(tetrahedron), 0);
  const Metrics& m = artifact<Metrics>(run_algorithm("skeleton_projection", tetrahedron), "metrics");
  EXPECT_EQ(m.at("inside_fraction"), 1.0) << metrics_json_for_test(m);
}

// A body (two legs) and an arm whose hand has three short fingers.
TEST(SkeletonMetrics, PruningSpursKeepsTheLimbs) {
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

TEST(SkeletonMetrics, DistanceBetweenTwoCircles) {
  const SkeletonDistance d = skeleton_distance(circle(2.0, 200), circle(2.1, 200));
  EXPECT_NEAR(d.hausdorff, 0.1, 0.002);
  EXPECT_NEAR(d.mean, 0.1, 0.002);
  EXPECT_NEAR(skeleton_distance(circle(2.0, 50), circle(2.0, 50)).hausdorff, 0.0, 1e-12);
}

TEST(SkeletonMcf, TorusGivesOneLoopAtItsCoreRadius) {
  const double R = 2, r = 0.5;
  const AlgorithmResult res = run_algorithm("skeleton_mcf", test::torus(R, r, 64, 24));
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
  const Metrics& m = artifact<Metrics>(res, "metrics");
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
  const AlgorithmResult res = run_algorithm("skeleton_mcf", capsule(r, h));
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
  const Metrics& m = artifact<Metrics>(res, "metrics");
  EXPECT_EQ(m.at("endpoints"), 2.0);
  EXPECT_EQ(m.at("junctions"), 0.0);
  EXPECT_EQ(m.at("loops"), 0.0);
  for (const Vec3& p : s.nodes) EXPECT_LT(std::hypot(p.x, p.y), 0.05 * r);
  const BBox box = bounding_box(s);
  EXPECT_GT(box.size().z, h);  // from near one cap's centre to near the other's
}

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
  const AlgorithmResult res = run_algorithm("skeleton_projection", test::torus(R, r, 64, 24));
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
  const Metrics& m = artifact<Metrics>(res, "metrics");
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
  const AlgorithmResult whole = run_algorithm("skeleton_projection", torus, {{"render_faces", 0LL}});
  const AlgorithmResult decimated = run_algorithm("skeleton_projection", torus, {{"render_faces", 8000LL}});
  const Skeleton& a = artifact<Skeleton>(whole, "skeleton");
  const Skeleton& b = artifact<Skeleton>(decimated, "skeleton");
  const Metrics& m = artifact<Metrics>(decimated, "metrics");
  EXPECT_EQ(artifact<Metrics>(whole, "metrics").at("faces_drawn"), double(torus.faces.size()));
  EXPECT_LE(m.at("faces_drawn"), 8000.0);
  EXPECT_GE(m.at("faces_drawn"), 2000.0);
  EXPECT_EQ(m.at("loops"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("endpoints"), 0.0);
  for (const Vec3& p : b.nodes) {
    EXPECT_NEAR(std::hypot(p.x, p.y), R, 0.02 * R);
    EXPECT_NEAR(p.z, 0.0, 0.02 * R);
  }
  const double voxel = 2 * (R + r) / 128;  // the default grid over the longest side
  EXPECT_LT(skeleton_distance(a, b).hausdorff, 2 * voxel);
}

TEST(SkeletonProjection, CapsuleGivesOneSegmentAlongItsAxis) {
  const double r = 0.5, h = 4;
  const AlgorithmResult res = run_algorithm("skeleton_projection", capsule(r, h));
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
  const Metrics& m = artifact<Metrics>(res, "metrics");
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
  const AlgorithmResult res = run_algorithm("skeleton_projection", plus);
  const Metrics& m = artifact<Metrics>(res, "metrics");
  EXPECT_EQ(m.at("endpoints"), 4.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("junctions"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("loops"), 0.0);
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
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
    const AlgorithmResult res = run_algorithm("skeleton_projection", mesh);
    const Metrics& m = artifact<Metrics>(res, "metrics");
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
  const Skeleton ours = artifact<Skeleton>(run_algorithm("skeleton_projection", mesh), "skeleton");
  const Skeleton mcf = artifact<Skeleton>(run_algorithm("skeleton_mcf", mesh), "skeleton");
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
  const AlgorithmResult res = run_algorithm("skeleton_projection", pipe);
  const Metrics& m = artifact<Metrics>(res, "metrics");
  EXPECT_EQ(m.at("inside_fraction"), 1.0) << metrics_json_for_test(m);
  EXPECT_EQ(m.at("loops"), 1.0) << metrics_json_for_test(m);
  const Skeleton& s = artifact<Skeleton>(res, "skeleton");
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
    const AlgorithmResult res = run_algorithm("skeleton_projection", mesh);
    const Metrics& m = artifact<Metrics>(res, "metrics");
    EXPECT_EQ(m.at("loops"), genus) << name << " " << metrics_json_for_test(m);
    EXPECT_EQ(m.at("inside_fraction"), 1.0) << name;
    EXPECT_EQ(m.at("components"), 1.0) << name;
  }
  const Mesh elephant = read_mesh(test::sample("elephant.off"));
  const std::vector<Vec3> mcf = loop_centres(artifact<Skeleton>(run_algorithm("skeleton_mcf", elephant), "skeleton"));
  ASSERT_EQ(mcf.size(), 3u);
  const double near = 0.06 * bounding_box(elephant).diagonal();
  for (const char* name : {"elephant.off", "refined_elephant.off"}) {
    const AlgorithmResult res = run_algorithm(
        "skeleton_projection", name == std::string("elephant.off") ? elephant : read_mesh(test::sample(name)));
    const std::vector<Vec3> ours = loop_centres(artifact<Skeleton>(res, "skeleton"));
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
    const Metrics& m = artifact<Metrics>(res, "metrics");
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
  const Skeleton s = skeleton::thin(votes, radius, skeleton::ProjectionParams{});
  std::vector<std::uint32_t> component;
  EXPECT_EQ(skeleton_components(s, component), 1u);
  double lo = 1e9, hi = -1e9;
  for (const Vec3& n : s.nodes) lo = std::min(lo, n.x), hi = std::max(hi, n.x);
  EXPECT_LT(lo, 10);
  EXPECT_GT(hi, 50);
}

TEST(SkeletonProjection, BadViewCounts) {
  const Mesh sphere = test::uv_sphere();
  for (long long views : {0LL, 3LL, 2000LL}) {
    try {
      run_algorithm("skeleton_projection", sphere, {{"views", views}});
      FAIL() << views << " views were taken";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("views"), std::string::npos) << e.what();
    }
  }
}

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
  Inputs in;
  in.add("mesh", two);
  in.add("skeleton", s);
  const AlgorithmResult res = run_algorithm("skeleton_segmentation", in);
  const ScalarField& f = artifact<ScalarField>(res, "branch");
  EXPECT_EQ(f.hint, ColorHint::categorical);
  const std::size_t half = two.faces.size() / 2;
  for (std::size_t i = 0; i < two.faces.size(); ++i) ASSERT_EQ(f.values[i], i < half ? f.values[0] : f.values[half]);
  EXPECT_NE(f.values[0], f.values[half]);
}

TEST(SkeletonBadInput, McfRefusesOpenAndNonManifoldMeshes) {
  try {
    run_algorithm("skeleton_mcf", test::grid(4));
    FAIL() << "an open mesh was taken";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("closed"), std::string::npos) << e.what();
  }
  Mesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_THROW(run_algorithm("skeleton_mcf", fin), InvalidInput);
  Inputs in;
  const Mesh sphere = test::uv_sphere();
  in.add("mesh", sphere);
  EXPECT_THROW(run_algorithm("skeleton_metrics", in), InvalidInput);  // no skeleton given
}

}  // namespace
}  // namespace cgview
