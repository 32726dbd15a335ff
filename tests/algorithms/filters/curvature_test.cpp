// curvature on shapes with known answers: 1/r and 1/r^2 on a sphere.
#include "filters/curvature.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "filter_shapes.h"
#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(Curvature, SphereIsOneOverRAndOneOverRSquared) {
  const double r = 2.0;
  const Mesh m = test::uv_sphere(r, 64, 128);
  const CurvatureResult res = curvature(m);
  const ScalarField& H = res.mean_curvature;
  const ScalarField& K = res.gaussian_curvature;
  ASSERT_EQ(H.values.size(), m.num_vertices());
  EXPECT_EQ(H.hint, ColorHint::symmetric);
  EXPECT_EQ(K.hint, ColorHint::symmetric);
  std::vector<double> h, k;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (std::abs(m.positions[v].z) < 0.8 * r) {
      h.push_back(H.values[v]);
      k.push_back(K.values[v]);
    }
  EXPECT_NEAR(median(h), 1 / r, 0.01 / r);  // 5% is required; measured under 0.1%
  EXPECT_NEAR(median(k), 1 / (r * r), 0.01 / (r * r));
}

TEST(Curvature, NonManifoldAndEmptyInputAreRefused) {
  EXPECT_NE(test::invalid_input_message([] { curvature(test::non_manifold()); }).find("manifold"), std::string::npos);
  Mesh points;
  points.positions = {{0, 0, 0}};
  EXPECT_NE(test::invalid_input_message([&] { curvature(points); }).find("no faces"), std::string::npos);
}

TEST(Curvature, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  curvature(test::box(), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(curvature(test::box(), {}, &cancelled), Cancelled);
}

TEST(Curvature, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("curvature").info.area, "filters"); }

}  // namespace
}  // namespace cgview
