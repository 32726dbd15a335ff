// The chaotic maps (chaos/maps.h) against hand computations and known
// periods, and the key-driven chaotic stream.
#include "chaos/maps.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <utility>
#include <vector>

#include "chaos/measures.h"
#include "chaos_samples.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosMapsTest, IkedaFirstIterateMatchesAHandComputation) {
  // t = 0.4 - 6 / (1 + 1) = -2.6; (1 + 0.9 cos t, 0.9 sin t).
  const chaos::Point2 p = chaos::ikeda_step({1, 0}, 0.9);
  EXPECT_NEAR(p.x, 0.2288001219679474, 1e-15);
  EXPECT_NEAR(p.y, -0.46395123463931776, 1e-15);
  const chaos::Point2 o = chaos::ikeda_step({0, 0}, 0.9);
  EXPECT_DOUBLE_EQ(o.x, 1.0);
  EXPECT_DOUBLE_EQ(o.y, 0.0);
}

TEST(ChaosMapsTest, HenonAndLogisticFirstIterates) {
  const chaos::Point2 h = chaos::henon_step({0.5, 0.2}, 1.4, 0.3);
  EXPECT_DOUBLE_EQ(h.x, 1 - 1.4 * 0.25 + 0.2);
  EXPECT_DOUBLE_EQ(h.y, 0.15);
  EXPECT_DOUBLE_EQ(chaos::logistic_step(0.25, 4.0), 0.75);
}

// The cat map on an N x N grid returns every point after the Pisano period
// of N / 2 steps (N = 5: 10, N = 10: 30, N = 101: 25, N = 2^k: 3 2^(k-2)),
// and not before.
TEST(ChaosMapsTest, CatMapIsPeriodicWithTheKnownPeriod) {
  for (const auto& [n, period] : std::vector<std::pair<std::uint32_t, int>>{{5, 10}, {10, 30}, {101, 25}, {64, 48}}) {
    int first_return = 0;
    for (int step = 1; step <= period && first_return == 0; ++step) {
      bool all_back = true;
      for (std::uint32_t i = 0; i < n && all_back; ++i)
        for (std::uint32_t j = 0; j < n && all_back; ++j) {
          std::array<std::uint32_t, 2> p{i, j};
          for (int s = 0; s < step; ++s) p = chaos::cat_step(p, n);
          all_back = p[0] == i && p[1] == j;
        }
      if (all_back) first_return = step;
    }
    EXPECT_EQ(first_return, period) << "N = " << n;
  }
}

TEST(ChaosMapsTest, CatMapOnAMeshReturnsAfterItsPeriod) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  chaos::MapParams p;
  p.kind = chaos::MapKind::cat;
  p.grid = 1024;  // period 768
  const auto start = chaos::apply_map(m.positions, p, 0).positions;
  const auto mid = chaos::apply_map(m.positions, p, 384).positions;
  const auto back = chaos::apply_map(m.positions, p, 768).positions;
  EXPECT_FALSE(test::bit_equal(start, mid));
  ASSERT_EQ(start.size(), back.size());
  for (std::size_t i = 0; i < start.size(); ++i) EXPECT_NEAR(norm(start[i] - back[i]), 0, 1e-9) << i;
}

TEST(ChaosMapsTest, StreamDependsOnEveryBitOfTheKey) {
  chaos::ChaoticStream a("d", "secret"), b("d", chaos::flip_one_bit("secret")), c("d", "secret");
  int same = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t x = a.next(), y = b.next();
    EXPECT_EQ(x, c.next());
    same += x == y;
  }
  EXPECT_LT(same, 3);
}

// The stream does not fall into a cycle (no 64-bit window of two words comes
// back within 1M words) and its bytes are about uniform.  A clamped
// perturbation once made 3,061 windows repeat here.
TEST(ChaosMapsTest, StreamHasNoShortCycleAndUniformBytes) {
  chaos::ChaoticStream s("d", "key");
  std::unordered_set<std::uint64_t> windows;
  std::vector<double> bytes(256, 0);
  std::uint32_t prev = s.next();
  const int n = 1 << 20;
  int repeats = 0;
  for (int i = 0; i < n; ++i) {
    const std::uint32_t w = s.next();
    repeats += !windows.insert(std::uint64_t(prev) << 32 | w).second;
    for (int b = 0; b < 4; ++b) ++bytes[w >> (8 * b) & 0xFF];
    prev = w;
  }
  EXPECT_EQ(repeats, 0);
  const double expect = 4.0 * n / 256;
  double chi2 = 0;
  for (double c : bytes) chi2 += (c - expect) * (c - expect) / expect;
  EXPECT_GT(chi2, 180);  // 255 degrees of freedom: about p = 0.0002 and 0.9998
  EXPECT_LT(chi2, 345);
}

}  // namespace
}  // namespace cgview
