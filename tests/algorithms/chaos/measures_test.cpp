// The measures of the encryption and steganography literature
// (chaos/measures.h) against brute force and hand computations.
#include "chaos/measures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "chaos/encrypt.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosMeasuresTest, HausdorffMatchesBruteForce) {
  const Mesh m = chaos::float32_copy(read_mesh(test::sample("elephant.off")));
  const Mesh c = chaos::encrypt(m, "k");
  std::vector<Vec3> a(m.positions.begin(), m.positions.begin() + 700),
      b(c.positions.begin(), c.positions.begin() + 900);
  auto directed = [](const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
    double worst = 0;
    for (const Vec3& p : x) {
      double best = 1e300;
      for (const Vec3& q : y) best = std::min(best, norm(p - q));
      worst = std::max(worst, best);
    }
    return worst;
  };
  EXPECT_DOUBLE_EQ(chaos::hausdorff_vertices(a, b), std::max(directed(a, b), directed(b, a)));
  EXPECT_DOUBLE_EQ(chaos::hausdorff_vertices(a, a), 0.0);
  const auto r = chaos::adjacent_correlation({{0, 0, 0}, {1, 2, 1}, {2, 4, 0}, {3, 6, 1}});
  EXPECT_NEAR(r[0], 1.0, 1e-12);
  EXPECT_NEAR(r[2], -1.0, 1e-12);
}

}  // namespace
}  // namespace cgview
