// VoxelGrid: indexing, point location, typed access, neighbourhoods and
// connected components, and the limits checked before allocating.
#include "core/voxel_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <set>
#include <tuple>

#include "core/errors.h"

namespace cgview {
namespace {

std::string construct_error(std::array<int, 3> dims, double size = 1.0, std::uint64_t max = std::uint64_t(1) << 31) {
  try {
    VoxelGrid g(dims, {0, 0, 0}, size, VoxelType::bit, max);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(VoxelGridTest, Construction) {
  const VoxelGrid g({3, 4, 5}, {1, 2, 3}, 0.5, VoxelType::uint8);
  EXPECT_EQ(g.dims(), (std::array<int, 3>{3, 4, 5}));
  EXPECT_EQ(g.origin(), (Vec3{1, 2, 3}));
  EXPECT_EQ(g.voxel_size(), 0.5);
  EXPECT_EQ(g.type(), VoxelType::uint8);
  EXPECT_EQ(g.size(), 60u);
  EXPECT_EQ(g.bytes().size(), 60u);
  EXPECT_TRUE(g.floats().empty());
  EXPECT_EQ(g.count_occupied(), 0u);

  const VoxelGrid f({2, 2, 2}, {0, 0, 0}, 1.0, VoxelType::float32);
  EXPECT_EQ(f.floats().size(), 8u);
  EXPECT_TRUE(f.bytes().empty());

  const VoxelGrid empty;
  EXPECT_EQ(empty.size(), 0u);
}

TEST(VoxelGridTest, LinearUnlinearRoundTrip) {
  const VoxelGrid g({3, 4, 5}, {0, 0, 0}, 1.0);
  // x fastest, then y, then z.
  EXPECT_EQ(g.linear({0, 0, 0}), 0u);
  EXPECT_EQ(g.linear({1, 0, 0}), 1u);
  EXPECT_EQ(g.linear({0, 1, 0}), 3u);
  EXPECT_EQ(g.linear({0, 0, 1}), 12u);
  EXPECT_EQ(g.linear({2, 3, 4}), 59u);
  std::set<std::size_t> seen;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        const VoxelIndex v{i, j, k};
        const std::size_t n = g.linear(v);
        EXPECT_LT(n, g.size());
        EXPECT_EQ(g.unlinear(n), v);
        seen.insert(n);
      }
  EXPECT_EQ(seen.size(), g.size());
  for (std::size_t n = 0; n < g.size(); ++n) EXPECT_EQ(g.linear(g.unlinear(n)), n);
}

TEST(VoxelGridTest, Contains) {
  const VoxelGrid g({3, 4, 5}, {0, 0, 0}, 1.0);
  EXPECT_TRUE(g.contains({0, 0, 0}));
  EXPECT_TRUE(g.contains({2, 3, 4}));
  EXPECT_FALSE(g.contains({3, 0, 0}));
  EXPECT_FALSE(g.contains({0, 4, 0}));
  EXPECT_FALSE(g.contains({0, 0, 5}));
  EXPECT_FALSE(g.contains({-1, 0, 0}));
  EXPECT_FALSE(g.contains({0, -1, 0}));
  EXPECT_FALSE(g.contains({0, 0, -1}));
}

TEST(VoxelGridTest, LocateAndCenter) {
  const VoxelGrid g({10, 10, 10}, {-1, 2, 0.5}, 0.25);
  EXPECT_EQ(g.center({0, 0, 0}), (Vec3{-0.875, 2.125, 0.625}));
  EXPECT_EQ(g.center({3, 1, 2}), (Vec3{-1 + 3.5 * 0.25, 2 + 1.5 * 0.25, 0.5 + 2.5 * 0.25}));
  for (int k = 0; k < 10; k += 3)
    for (int j = 0; j < 10; j += 2)
      for (int i = 0; i < 10; ++i) EXPECT_EQ(g.locate(g.center({i, j, k})), (VoxelIndex{i, j, k}));
  EXPECT_EQ(g.locate({-1, 2, 0.5}), (VoxelIndex{0, 0, 0}));          // the origin corner is inside voxel 0
  EXPECT_EQ(g.locate({-0.75, 2.25, 0.75}), (VoxelIndex{1, 1, 1}));   // a lower corner belongs to its voxel
  EXPECT_EQ(g.locate({-1.01, 1.9, 0.4}), (VoxelIndex{-1, -1, -1}));  // outside: floor, not truncation
  EXPECT_FALSE(g.contains(g.locate({-1.01, 2.1, 0.6})));
  // Far away or NaN: some index outside the grid, never undefined behaviour.
  EXPECT_FALSE(g.contains(g.locate({1e300, 2.1, 0.6})));
  EXPECT_FALSE(g.contains(g.locate({-1e300, 2.1, 0.6})));
  EXPECT_FALSE(g.contains(g.locate({-0.9, std::numeric_limits<double>::quiet_NaN(), 0.6})));
  EXPECT_FALSE(g.contains(g.locate({-0.9, 2.1, std::numeric_limits<double>::infinity()})));
  EXPECT_EQ(g.locate({1e300, 2.1, 0.6}).i, std::numeric_limits<int>::max());
  EXPECT_EQ(g.locate({-1e300, 2.1, 0.6}).i, std::numeric_limits<int>::min());
  EXPECT_EQ(g.locate({1.5, 2, 0.5}), (VoxelIndex{10, 0, 0}));
  EXPECT_FALSE(g.contains(g.locate({1.5, 2, 0.5})));
}

TEST(VoxelGridTest, BitAccess) {
  VoxelGrid g({4, 4, 4}, {0, 0, 0}, 1.0, VoxelType::bit);
  g.set({1, 2, 3}, 5.f);
  g.set({0, 0, 0}, 0.5f);
  g.set({3, 3, 3}, 1.f);
  g.set({3, 3, 3}, 0.f);
  EXPECT_EQ(g.get({1, 2, 3}), 1.f);
  EXPECT_EQ(g.get({0, 0, 0}), 1.f);
  EXPECT_EQ(g.get({3, 3, 3}), 0.f);
  EXPECT_EQ(g.get({2, 2, 2}), 0.f);
  EXPECT_EQ(g.bytes()[g.linear({1, 2, 3})], 1);
  EXPECT_EQ(g.count_occupied(), 2u);
  EXPECT_TRUE(g.occupied({1, 2, 3}));
  EXPECT_FALSE(g.occupied({3, 3, 3}));
  EXPECT_FALSE(g.occupied({-1, 0, 0}));  // outside is empty, not an error
  EXPECT_FALSE(g.occupied({4, 4, 4}));
}

TEST(VoxelGridTest, Uint8AccessClamps) {
  VoxelGrid g({4, 1, 1}, {0, 0, 0}, 1.0, VoxelType::uint8);
  g.set({0, 0, 0}, 300.f);
  g.set({1, 0, 0}, -5.f);
  g.set({2, 0, 0}, 12.f);
  g.set({3, 0, 0}, 255.f);
  EXPECT_EQ(g.get({0, 0, 0}), 255.f);
  EXPECT_EQ(g.get({1, 0, 0}), 0.f);
  EXPECT_EQ(g.get({2, 0, 0}), 12.f);
  EXPECT_EQ(g.get({3, 0, 0}), 255.f);
  EXPECT_EQ(g.count_occupied(), 3u);
  g.bytes()[1] = 7;
  EXPECT_EQ(g.get({1, 0, 0}), 7.f);
}

TEST(VoxelGridTest, FloatAccess) {
  VoxelGrid g({2, 2, 2}, {0, 0, 0}, 1.0, VoxelType::float32);
  g.set({1, 1, 1}, -0.25f);
  g.set({0, 1, 0}, 1e6f);
  EXPECT_EQ(g.get({1, 1, 1}), -0.25f);
  EXPECT_EQ(g.get({0, 1, 0}), 1e6f);
  EXPECT_EQ(g.get({0, 0, 0}), 0.f);
  EXPECT_EQ(g.floats()[7], -0.25f);
  EXPECT_EQ(g.count_occupied(), 2u);
  EXPECT_TRUE(g.occupied({1, 1, 1}));  // a negative value is occupied
}

TEST(VoxelGridTest, Offsets) {
  const auto& six = VoxelGrid::offsets(Connectivity::six);
  const auto& eighteen = VoxelGrid::offsets(Connectivity::eighteen);
  const auto& all = VoxelGrid::offsets(Connectivity::twenty_six);
  EXPECT_EQ(six.size(), 6u);
  EXPECT_EQ(eighteen.size(), 18u);
  EXPECT_EQ(all.size(), 26u);
  auto nonzero = [](const VoxelIndex& o) { return (o.i != 0) + (o.j != 0) + (o.k != 0); };
  for (const auto& o : six) EXPECT_EQ(nonzero(o), 1);
  for (const auto& o : eighteen) EXPECT_TRUE(nonzero(o) == 1 || nonzero(o) == 2);
  for (const auto& o : all) EXPECT_GE(nonzero(o), 1);
  // Distinct, and each list contains the smaller one.
  std::set<std::tuple<int, int, int>> s26;
  for (const auto& o : all) s26.insert({o.i, o.j, o.k});
  EXPECT_EQ(s26.size(), 26u);
  for (const auto& o : eighteen) EXPECT_TRUE(s26.count({o.i, o.j, o.k}));
  for (const auto& o : six) EXPECT_TRUE(std::find(eighteen.begin(), eighteen.end(), o) != eighteen.end());
}

TEST(VoxelGridTest, ForEachNeighborClipsToGrid) {
  const VoxelGrid g({3, 3, 3}, {0, 0, 0}, 1.0);
  auto count = [&](VoxelIndex v, Connectivity c) {
    int n = 0;
    g.for_each_neighbor(v, c, [&](VoxelIndex w) {
      EXPECT_TRUE(g.contains(w));
      EXPECT_NE(w, v);
      ++n;
    });
    return n;
  };
  EXPECT_EQ(count({1, 1, 1}, Connectivity::six), 6);
  EXPECT_EQ(count({1, 1, 1}, Connectivity::eighteen), 18);
  EXPECT_EQ(count({1, 1, 1}, Connectivity::twenty_six), 26);
  EXPECT_EQ(count({0, 0, 0}, Connectivity::six), 3);
  EXPECT_EQ(count({0, 0, 0}, Connectivity::eighteen), 6);
  EXPECT_EQ(count({0, 0, 0}, Connectivity::twenty_six), 7);
  EXPECT_EQ(count({1, 0, 0}, Connectivity::six), 4);
}

std::uint32_t components_of(std::initializer_list<VoxelIndex> on, Connectivity c,
                            std::vector<std::uint32_t>* labels = nullptr, VoxelGrid* out = nullptr) {
  VoxelGrid g({4, 4, 4}, {0, 0, 0}, 1.0);
  for (const auto& v : on) g.set(v, 1);
  std::vector<std::uint32_t> l;
  const std::uint32_t n = g.components(c, l);
  if (labels) *labels = l;
  if (out) *out = g;
  return n;
}

TEST(VoxelGridTest, ComponentsFaceTouching) {
  for (Connectivity c : {Connectivity::six, Connectivity::eighteen, Connectivity::twenty_six})
    EXPECT_EQ(components_of({{1, 1, 1}, {2, 1, 1}}, c), 1u);
}

TEST(VoxelGridTest, ComponentsEdgeTouching) {
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 1}}, Connectivity::six), 2u);
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 1}}, Connectivity::eighteen), 1u);
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 1}}, Connectivity::twenty_six), 1u);
}

TEST(VoxelGridTest, ComponentsCornerTouching) {
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 2}}, Connectivity::six), 2u);
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 2}}, Connectivity::eighteen), 2u);
  EXPECT_EQ(components_of({{1, 1, 1}, {2, 2, 2}}, Connectivity::twenty_six), 1u);
}

TEST(VoxelGridTest, ComponentLabels) {
  std::vector<std::uint32_t> labels;
  VoxelGrid g;
  // An L of three face-connected voxels, and a lone one far away.
  const auto n = components_of({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {3, 3, 3}}, Connectivity::six, &labels, &g);
  ASSERT_EQ(n, 2u);
  ASSERT_EQ(labels.size(), 64u);
  EXPECT_EQ(labels[g.linear({0, 0, 0})], 1u);
  EXPECT_EQ(labels[g.linear({1, 0, 0})], 1u);
  EXPECT_EQ(labels[g.linear({1, 1, 0})], 1u);
  EXPECT_EQ(labels[g.linear({3, 3, 3})], 2u);
  std::size_t zeros = std::count(labels.begin(), labels.end(), 0u);
  EXPECT_EQ(zeros, 60u);  // empty voxels are 0
}

TEST(VoxelGridTest, ComponentsOfEmptyAndFullGrids) {
  std::vector<std::uint32_t> labels;
  VoxelGrid g({5, 4, 3}, {0, 0, 0}, 1.0, VoxelType::float32);
  EXPECT_EQ(g.components(Connectivity::six, labels), 0u);
  EXPECT_EQ(labels, std::vector<std::uint32_t>(60, 0));
  for (std::size_t n = 0; n < g.size(); ++n) g.set(g.unlinear(n), 0.5f);
  EXPECT_EQ(g.components(Connectivity::six, labels), 1u);
  EXPECT_EQ(labels, std::vector<std::uint32_t>(60, 1));
}

TEST(VoxelGridTest, ComponentsOfCheckerboardSlab) {
  // Alternate voxels of a 4x4x1 slab: 8 under 6-connectivity, 1 under 18.
  VoxelGrid g({4, 4, 1}, {0, 0, 0}, 1.0);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      if ((i + j) % 2 == 0) g.set({i, j, 0}, 1);
  std::vector<std::uint32_t> labels;
  EXPECT_EQ(g.components(Connectivity::six, labels), 8u);
  EXPECT_EQ(g.components(Connectivity::eighteen, labels), 1u);
  EXPECT_EQ(g.components(Connectivity::twenty_six, labels), 1u);
}

TEST(VoxelGridTest, ConstructorRejectsBadDimensions) {
  std::string msg = construct_error({0, 4, 4});
  EXPECT_NE(msg.find("dimensions must be positive"), std::string::npos) << msg;
  EXPECT_NE(msg.find("got 0"), std::string::npos) << msg;
  msg = construct_error({4, 4, -2});
  EXPECT_NE(msg.find("got -2"), std::string::npos) << msg;
  EXPECT_THROW(VoxelGrid({4, 0, 4}, {0, 0, 0}, 1.0), InvalidInput);
}

TEST(VoxelGridTest, ConstructorRejectsBadSizeAndOrigin) {
  EXPECT_THROW(VoxelGrid({2, 2, 2}, {0, 0, 0}, 0.0), InvalidInput);
  EXPECT_THROW(VoxelGrid({2, 2, 2}, {0, 0, 0}, -1.0), InvalidInput);
  EXPECT_THROW(VoxelGrid({2, 2, 2}, {0, 0, 0}, std::numeric_limits<double>::quiet_NaN()), InvalidInput);
  EXPECT_THROW(VoxelGrid({2, 2, 2}, {0, 0, 0}, std::numeric_limits<double>::infinity()), InvalidInput);
  EXPECT_THROW(VoxelGrid({2, 2, 2}, {0, std::numeric_limits<double>::quiet_NaN(), 0}, 1.0), InvalidInput);
}

TEST(VoxelGridTest, ConstructorRejectsTooManyVoxelsWithoutAllocating) {
  // 2^31 - 1 cubed would be ~10^28 voxels; the count must not overflow or
  // be allocated before the check.
  const int big = std::numeric_limits<int>::max();
  std::string msg = construct_error({big, big, big});
  EXPECT_NE(msg.find("over the limit"), std::string::npos) << msg;
  msg = construct_error({100000, 100000, 100000});
  EXPECT_NE(msg.find("100000x100000x100000"), std::string::npos) << msg;
  EXPECT_NE(msg.find("1000000000000000"), std::string::npos) << msg;
  // 2^21 * 2^21 * 2^22 = 2^64 wraps to 0 in 64 bits: still far over the limit.
  msg = construct_error({1 << 21, 1 << 21, 1 << 22});
  EXPECT_NE(msg.find("over the limit"), std::string::npos) << msg;
  EXPECT_THROW(VoxelGrid({1 << 22, 1 << 21, 1 << 21}, {0, 0, 0}, 1.0, VoxelType::float32), InvalidInput);
  // A custom limit: exactly at it is fine, one over is not.
  EXPECT_NO_THROW(VoxelGrid({10, 10, 10}, {0, 0, 0}, 1.0, VoxelType::bit, 1000));
  EXPECT_THROW(VoxelGrid({10, 10, 11}, {0, 0, 0}, 1.0, VoxelType::bit, 1000), InvalidInput);
}

}  // namespace
}  // namespace cgview
