// The Morton order of points (sdf/curve_order.h) against the same codes made
// another way: the three coordinates' ten bits taken in turn from the
// highest, and the indices sorted stably by them.
#include "sdf/curve_order.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

namespace cgview::sdf {
namespace {

std::vector<std::uint32_t> reference_order(const std::vector<Vec3>& p) {
  Vec3 lo = p[0], hi = p[0];
  for (const Vec3& c : p)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  std::vector<std::uint32_t> code(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    std::uint32_t q[3];
    for (int a = 0; a < 3; ++a) q[a] = hi[a] > lo[a] ? std::uint32_t((p[i][a] - lo[a]) / (hi[a] - lo[a]) * 1023.0) : 0;
    for (int bit = 9; bit >= 0; --bit)  // x the highest of each triple
      for (int a = 0; a < 3; ++a) code[i] = code[i] << 1 | ((q[a] >> bit) & 1);
  }
  std::vector<std::uint32_t> order(p.size());
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) { return code[a] < code[b]; });
  return order;
}

TEST(CurveOrder, SortsPointsByTheirInterleavedBitsKeepingTiesInOrder) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-3, 7);
  std::vector<Vec3> p(20000);
  for (Vec3& c : p) c = {u(rng), u(rng) * 0.01, u(rng) * 100};  // boxes of any shape: each axis on its own
  // Repeated points: one code, kept in their given order.
  for (std::size_t i = 0; i < 500; ++i) p[10000 + i] = p[i];
  EXPECT_EQ(curve_order(p), reference_order(p));
}

// Above 128k points the radix passes split the points over the cores (on a
// machine of two or more): the same order.
TEST(CurveOrder, ManyPointsSortAlikeOnSeveralThreads) {
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> p(300000);
  for (Vec3& c : p) c = {u(rng), u(rng), u(rng) * u(rng)};
  for (std::size_t i = 0; i < 20000; ++i) p[150000 + i * 7] = p[i * 13];
  EXPECT_EQ(curve_order(p), reference_order(p));
}

TEST(CurveOrder, NearInTheOrderMeansNearInSpace) {
  // A grid's points shuffled: consecutive points along the curve are
  // neighbours far more often than in the shuffled order.
  std::vector<Vec3> p;
  for (int x = 0; x < 32; ++x)
    for (int y = 0; y < 32; ++y)
      for (int z = 0; z < 32; ++z) p.push_back({double(x), double(y), double(z)});
  std::shuffle(p.begin(), p.end(), std::mt19937(3));
  const std::vector<std::uint32_t> order = curve_order(p);
  double along = 0, given = 0;
  for (std::size_t i = 1; i < p.size(); ++i)
    along += norm(p[order[i]] - p[order[i - 1]]), given += norm(p[i] - p[i - 1]);
  EXPECT_LT(along / double(p.size() - 1), 1.5);  // a Z-curve on a grid: mostly single steps
  EXPECT_GT(given / double(p.size() - 1), 10.0);
}

TEST(CurveOrder, EmptyAndDegenerateBoxes) {
  EXPECT_TRUE(curve_order(std::vector<Vec3>{}).empty());
  const std::vector<Vec3> same(7, Vec3{1, 2, 3});
  const std::vector<std::uint32_t> order = curve_order(same);
  for (std::uint32_t i = 0; i < 7; ++i) EXPECT_EQ(order[i], i);
}

}  // namespace
}  // namespace cgview::sdf
