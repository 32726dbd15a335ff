// curvature on shapes with known answers: 1/r and 1/r^2 on a sphere.
#include "filters/curvature.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "filter_shapes.h"
#include "filters/vertex_curvatures.h"
#include "invalid_input.h"
#include "non_manifold_shapes.h"
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

TEST(Curvature, TwoBoxesSharingAnEdgeAreMeasuredOnARepairedCopyByDefault) {
  // The reference: the two boxes apart (manifold), each vertex of the shared
  // edge the mean of its two corners.
  const Mesh apart = test::merged(test::box({0, 0, 0}, {1, 1, 1}), test::box({1, 1, 0}, {2, 2, 1}));
  const Mesh broken = test::two_boxes_sharing_an_edge(), before = broken;
  const VertexCurvatures ref = vertex_curvatures(apart);
  const CurvatureResult r = curvature(broken);
  test::expect_same_mesh(broken, before);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("curvature: the mesh was not manifold", 0), 0u) << r.warnings[0];
  ASSERT_EQ(r.mean_curvature.values.size(), broken.num_vertices());
  for (std::size_t i = 0; i < broken.num_vertices(); ++i) {
    double h = 0, k = 0;
    int n = 0;
    for (std::size_t j = 0; j < apart.num_vertices(); ++j)
      if (apart.positions[j] == broken.positions[i]) h += ref.mean[j], k += ref.gaussian[j], ++n;
    ASSERT_GT(n, 0);
    EXPECT_NEAR(r.mean_curvature.values[i], h / n, 1e-5) << i;
    EXPECT_NEAR(r.gaussian_curvature.values[i], k / n, 1e-5) << i;
  }
  CurvatureParams off;
  off.repair = false;
  const std::string what = test::invalid_input_message([&] { curvature(broken, off); });
  EXPECT_NE(what.find("curvature needs a manifold mesh"), std::string::npos) << what;
  EXPECT_NE(what.find("set 'repair'"), std::string::npos) << what;
}

TEST(Curvature, NonManifoldWithoutRepairAndEmptyInputAreRefused) {
  EXPECT_NE(test::invalid_input_message([] { curvature(test::non_manifold(), {.repair = false}); }).find("manifold"),
            std::string::npos);
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
