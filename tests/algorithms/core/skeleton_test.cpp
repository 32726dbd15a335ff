// Skeleton: validation, degrees, lengths, components and branch extraction.
#include "core/skeleton.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/errors.h"

namespace cgview {
namespace {

std::string validate_error(const Skeleton& s) {
  try {
    s.validate();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

// A Y: node 0 at the junction, three arms of two edges each.
Skeleton y_shape() {
  Skeleton s;
  s.nodes = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {0, 2, 0}, {0, 0, 1}, {0, 0, 2}};
  s.edges = {{0, 1}, {1, 2}, {0, 3}, {3, 4}, {5, 0}, {6, 5}};
  return s;
}

// A circle of n nodes and radius r in the z = 0 plane.
Skeleton ring(int n, double r = 1.0) {
  Skeleton s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    s.nodes.push_back({r * std::cos(a), r * std::sin(a), 0});
    s.edges.push_back({Index(i), Index((i + 1) % n)});
  }
  return s;
}

// The nodes of a path, as a set of undirected edges (to compare paths
// regardless of direction).
std::vector<std::array<Index, 2>> path_edges(const std::vector<Index>& path) {
  std::vector<std::array<Index, 2>> out;
  for (std::size_t i = 1; i < path.size(); ++i)
    out.push_back({std::min(path[i - 1], path[i]), std::max(path[i - 1], path[i])});
  std::sort(out.begin(), out.end());
  return out;
}

TEST(SkeletonTest, ValidateAcceptsGoodSkeletons) {
  EXPECT_NO_THROW(Skeleton{}.validate());
  EXPECT_NO_THROW(y_shape().validate());
  Skeleton s = ring(5);
  s.radii.assign(5, 0.1f);
  EXPECT_NO_THROW(s.validate());
}

TEST(SkeletonTest, ValidateErrors) {
  Skeleton s = y_shape();
  s.edges[4] = {0, 7};
  std::string msg = validate_error(s);
  EXPECT_NE(msg.find("edge 4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("node 7"), std::string::npos) << msg;
  EXPECT_NE(msg.find("only 7"), std::string::npos) << msg;

  s = y_shape();
  s.edges[2] = {3, 3};
  msg = validate_error(s);
  EXPECT_NE(msg.find("edge 2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("itself"), std::string::npos) << msg;

  s = y_shape();
  s.nodes[6].x = std::numeric_limits<double>::quiet_NaN();
  msg = validate_error(s);
  EXPECT_NE(msg.find("node 6"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not finite"), std::string::npos) << msg;

  s = y_shape();
  s.radii.assign(3, 1.f);
  msg = validate_error(s);
  EXPECT_NE(msg.find("3 radii"), std::string::npos) << msg;
  EXPECT_NE(msg.find("7 nodes"), std::string::npos) << msg;
}

TEST(SkeletonTest, Degrees) {
  const auto d = node_degrees(y_shape());
  EXPECT_EQ(d, (std::vector<std::uint32_t>{3, 2, 1, 2, 1, 2, 1}));
  const auto r = node_degrees(ring(6));
  EXPECT_EQ(r, std::vector<std::uint32_t>(6, 2));
  Skeleton lone;
  lone.nodes = {{0, 0, 0}};
  EXPECT_EQ(node_degrees(lone), std::vector<std::uint32_t>{0});
}

TEST(SkeletonTest, Adjacency) {
  const Adjacency a = skeleton_adjacency(y_shape());
  ASSERT_EQ(a.size(), 7u);
  EXPECT_EQ(a.items.size(), 12u);
  std::vector<std::uint32_t> n0(a.begin(0), a.end(0));
  std::sort(n0.begin(), n0.end());
  EXPECT_EQ(n0, (std::vector<std::uint32_t>{1, 3, 5}));
  EXPECT_EQ(std::vector<std::uint32_t>(a.begin(6), a.end(6)), std::vector<std::uint32_t>{5});
}

TEST(SkeletonTest, TotalLength) {
  EXPECT_DOUBLE_EQ(total_length(y_shape()), 6.0);
  Skeleton s;
  s.nodes = {{0, 0, 0}, {3, 4, 0}, {3, 4, 12}};
  s.edges = {{0, 1}, {1, 2}};
  EXPECT_DOUBLE_EQ(total_length(s), 17.0);
  EXPECT_EQ(total_length(Skeleton{}), 0.0);
}

TEST(SkeletonTest, CircleLengthApproachesCircumference) {
  // The curve skeleton of a torus of major radius R is its core circle.
  const double R = 2.0;
  const Skeleton s = ring(256, R);
  const double want = 2 * std::numbers::pi * R;
  EXPECT_NEAR(total_length(s), want, 1e-4 * want);
  EXPECT_LT(total_length(s), want);  // inscribed polygon
  const BBox b = bounding_box(s);
  EXPECT_NEAR(b.min.x, -R, 1e-12);
  EXPECT_NEAR(b.max.x, R, 1e-12);
  EXPECT_NEAR(b.max.y, R, 1e-3);
  EXPECT_EQ(b.min.z, 0.0);
  EXPECT_EQ(b.max.z, 0.0);
}

TEST(SkeletonTest, Components) {
  std::vector<std::uint32_t> comp;
  EXPECT_EQ(skeleton_components(y_shape(), comp), 1u);
  EXPECT_EQ(comp, std::vector<std::uint32_t>(7, 0));

  // A Y, a ring of 4 and a lone node.
  Skeleton s = y_shape();
  const Skeleton r = ring(4);
  const Index off = Index(s.nodes.size());
  s.nodes.insert(s.nodes.end(), r.nodes.begin(), r.nodes.end());
  for (auto e : r.edges) s.edges.push_back({e[0] + off, e[1] + off});
  s.nodes.push_back({9, 9, 9});
  ASSERT_NO_THROW(s.validate());
  EXPECT_EQ(skeleton_components(s, comp), 3u);
  ASSERT_EQ(comp.size(), 12u);
  for (int i = 0; i < 7; ++i) EXPECT_EQ(comp[i], 0u);
  for (int i = 7; i < 11; ++i) EXPECT_EQ(comp[i], 1u);
  EXPECT_EQ(comp[11], 2u);

  EXPECT_EQ(skeleton_components(Skeleton{}, comp), 0u);
}

TEST(SkeletonTest, BranchesOfY) {
  const Skeleton s = y_shape();
  const auto branches = skeleton_branches(s);
  ASSERT_EQ(branches.size(), 3u);
  std::vector<std::vector<std::array<Index, 2>>> got;
  for (const auto& b : branches) {
    ASSERT_EQ(b.size(), 3u);
    // From the junction to a leaf, or back.
    EXPECT_TRUE(b.front() == 0 || b.back() == 0);
    got.push_back(path_edges(b));
  }
  std::sort(got.begin(), got.end());
  std::vector<std::vector<std::array<Index, 2>>> want = {path_edges({0, 1, 2}), path_edges({0, 3, 4}),
                                                         path_edges({0, 5, 6})};
  std::sort(want.begin(), want.end());
  EXPECT_EQ(got, want);
}

TEST(SkeletonTest, BranchesOfPath) {
  Skeleton s;
  s.nodes = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};
  s.edges = {{1, 2}, {0, 1}, {2, 3}};
  const auto branches = skeleton_branches(s);
  ASSERT_EQ(branches.size(), 1u);
  EXPECT_EQ(branches[0], (std::vector<Index>{0, 1, 2, 3}));
}

TEST(SkeletonTest, BranchesOfRingIsOneClosedPath) {
  const Skeleton s = ring(6);
  const auto branches = skeleton_branches(s);
  ASSERT_EQ(branches.size(), 1u);
  const auto& p = branches[0];
  ASSERT_EQ(p.size(), 7u);
  EXPECT_EQ(p.front(), p.back());
  std::vector<Index> inner(p.begin(), p.end() - 1);
  std::sort(inner.begin(), inner.end());
  EXPECT_EQ(inner, (std::vector<Index>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(path_edges(p), path_edges({0, 1, 2, 3, 4, 5, 0}));
}

TEST(SkeletonTest, BranchesCoverEveryEdgeOnce) {
  // A ring with a tail: junction at node 0 (ring 0..4, tail 0-5-6), plus a
  // separate ring of 3 and a separate single edge.
  Skeleton s = ring(5);
  s.nodes.push_back({2, 0, 0});
  s.nodes.push_back({3, 0, 0});
  s.edges.push_back({0, 5});
  s.edges.push_back({5, 6});
  const Skeleton r = ring(3);
  const Index off = Index(s.nodes.size());
  s.nodes.insert(s.nodes.end(), r.nodes.begin(), r.nodes.end());
  for (auto e : r.edges) s.edges.push_back({e[0] + off, e[1] + off});
  s.nodes.push_back({5, 5, 5});
  s.nodes.push_back({6, 5, 5});
  s.edges.push_back({Index(s.nodes.size() - 2), Index(s.nodes.size() - 1)});
  ASSERT_NO_THROW(s.validate());

  const auto branches = skeleton_branches(s);
  // The loop through the junction, the tail, the separate ring, the edge.
  ASSERT_EQ(branches.size(), 4u);
  std::vector<std::array<Index, 2>> walked;
  for (const auto& b : branches) {
    const auto e = path_edges(b);
    walked.insert(walked.end(), e.begin(), e.end());
  }
  std::sort(walked.begin(), walked.end());
  std::vector<std::array<Index, 2>> all;
  for (auto e : s.edges) all.push_back({std::min(e[0], e[1]), std::max(e[0], e[1])});
  std::sort(all.begin(), all.end());
  EXPECT_EQ(walked, all);
  // The loop through the junction starts and ends there.
  int loops_at_junction = 0;
  for (const auto& b : branches)
    if (b.size() == 6 && b.front() == 0 && b.back() == 0) ++loops_at_junction;
  EXPECT_EQ(loops_at_junction, 1);
}

TEST(SkeletonTest, BranchesWithParallelEdges) {
  // Two nodes joined twice: a cycle of two edges.
  Skeleton s;
  s.nodes = {{0, 0, 0}, {1, 0, 0}};
  s.edges = {{0, 1}, {1, 0}};
  const auto branches = skeleton_branches(s);
  ASSERT_EQ(branches.size(), 1u);
  EXPECT_EQ(branches[0].size(), 3u);
  EXPECT_EQ(branches[0].front(), branches[0].back());
}

TEST(SkeletonTest, BranchesOfEmptyAndLoneNodes) {
  EXPECT_TRUE(skeleton_branches(Skeleton{}).empty());
  Skeleton s;
  s.nodes = {{0, 0, 0}, {1, 1, 1}};
  EXPECT_TRUE(skeleton_branches(s).empty());
}

}  // namespace
}  // namespace cgview
