// estimate_normals: on a sphere and a torus sampled with their exact normals,
// both fits come within a few degrees of them, and the orientation turns
// every one outward; bad parameters and clouds are refused.
#include "points/estimate_normals.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "invalid_input.h"
#include "point_shapes.h"

namespace cgview {
namespace {

struct Spread {
  double max_deg = 0, mean_deg = 0;
  std::size_t inward = 0;  // normals on the analytic one's far side
};

// How far the estimated normals are from the exact ones.
Spread compare(const PointCloud& exact, const PointCloud& estimated) {
  Spread s;
  for (std::size_t i = 0; i < exact.size(); ++i) {
    const Vec3 a = to_double(exact.normals[i]), b = to_double(estimated.normals[i]);
    EXPECT_NEAR(norm(b), 1.0, 1e-5) << "point " << i;
    const double d = test::line_angle_deg(a, b);
    s.max_deg = std::max(s.max_deg, d);
    s.mean_deg += d / double(exact.size());
    s.inward += dot(a, b) < 0;
  }
  return s;
}

PointCloud without_normals(PointCloud c) {
  c.normals.clear();
  return c;
}

class EstimateNormalsMethods : public ::testing::TestWithParam<NormalMethod> {};

TEST_P(EstimateNormalsMethods, SphereNormalsAreRadialAndOutward) {
  const PointCloud exact = test::sphere_cloud(3000, 2.0, {1, -2, 0.5});
  const EstimateNormalsResult r = estimate_normals(without_normals(exact), {.method = GetParam()});
  ASSERT_EQ(r.points.normals.size(), exact.size());
  EXPECT_EQ(r.points.positions, exact.positions);
  const Spread s = compare(exact, r.points);
  EXPECT_LT(s.max_deg, 3.0);
  EXPECT_LT(s.mean_deg, 1.0);
  EXPECT_EQ(s.inward, 0u);
  EXPECT_TRUE(r.warnings.empty()) << r.warnings[0];
}

TEST_P(EstimateNormalsMethods, TorusNormalsAreOutward) {
  const PointCloud exact = test::torus_cloud(120, 40);
  const EstimateNormalsResult r = estimate_normals(without_normals(exact), {.method = GetParam()});
  const Spread s = compare(exact, r.points);
  EXPECT_LT(s.max_deg, 5.0);
  EXPECT_LT(s.mean_deg, 2.0);
  EXPECT_EQ(s.inward, 0u);
}

// Unoriented: the lines are right, the sides are the fit's own.
TEST_P(EstimateNormalsMethods, WithoutOrientationOnlyTheLinesAreRight) {
  const PointCloud exact = test::sphere_cloud(2000);
  const EstimateNormalsResult r =
      estimate_normals(without_normals(exact), {.method = GetParam(), .neighbors = 12, .orient = false});
  EXPECT_LT(compare(exact, r.points).max_deg, 3.0);
}

INSTANTIATE_TEST_SUITE_P(JetAndPca, EstimateNormalsMethods, ::testing::Values(NormalMethod::jet, NormalMethod::pca),
                         [](const auto& info) { return info.param == NormalMethod::jet ? "jet" : "pca"; });

TEST(EstimateNormals, ColoursAreKeptAndNormalsReplaced) {
  PointCloud c = test::sphere_cloud(500);
  c.colors.assign(c.size(), Color{10, 20, 30, 255});
  for (Vec3f& n : c.normals) n = n * -1.0f;  // inward: replaced, then turned out
  const EstimateNormalsResult r = estimate_normals(c);
  EXPECT_EQ(r.points.colors, c.colors);
  EXPECT_EQ(compare(test::sphere_cloud(500), r.points).inward, 0u);
}

// Two spheres far apart: the neighbour graph has two pieces, and the tree
// from the highest point reaches only its own.
TEST(EstimateNormals, PointsTheTreeCannotReachAreAWarning) {
  PointCloud c = test::sphere_cloud(400);
  const PointCloud far = test::sphere_cloud(300, 1.0, {100, 0, 0});
  c.positions.insert(c.positions.end(), far.positions.begin(), far.positions.end());
  c.normals.clear();
  const EstimateNormalsResult r = estimate_normals(c, {.method = NormalMethod::pca});
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("300 of 700 points could not be oriented"), std::string::npos) << r.warnings[0];
}

TEST(EstimateNormals, BadParametersAndCloudsAreRefused) {
  const PointCloud c = test::sphere_cloud(100);
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(c, {.neighbors = 2}); }).find("'neighbors'"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(c, {.neighbors = 501}); }).find("'neighbors'"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(c, {.method = NormalMethod(7)}); }).find("'method'"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(PointCloud{}); }).find("at least 6 points"),
            std::string::npos);
  PointCloud five = test::sphere_cloud(5);
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(five); }).find("the cloud has 5"), std::string::npos);
  EXPECT_NO_THROW(estimate_normals(five, {.method = NormalMethod::pca}));
  PointCloud nan = c;
  nan.positions[3].y = NAN;
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(nan); }).find("point 3"), std::string::npos);
  PointCloud uneven = c;
  uneven.normals.pop_back();
  EXPECT_NE(test::invalid_input_message([&] { estimate_normals(uneven); }).find("99 normals"), std::string::npos);
}

TEST(EstimateNormals, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  estimate_normals(test::sphere_cloud(200), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(estimate_normals(test::sphere_cloud(200), {}, &cancelled), Cancelled);
}

// As a job runs it: the cloud as the input "points", the cloud back as the
// artifact "points".
TEST(EstimateNormals, RegisteredWithAPointsInputAndOutput) {
  const Algorithm& a = find_algorithm("estimate_normals");
  EXPECT_EQ(a.info.area, "points");
  ASSERT_EQ(a.info.inputs.size(), 1u);
  EXPECT_EQ(a.info.inputs[0].name, "points");
  EXPECT_EQ(a.info.inputs[0].kind, OutputKind::points);
  const PointCloud exact = test::sphere_cloud(1000);
  const PointCloud bare = without_normals(exact);
  Inputs in;
  in.add("points", bare);
  Context ctx;
  const AlgorithmResult r = a.run(in, {{"method", std::string("pca")}, {"neighbors", 12LL}}, ctx);
  ASSERT_EQ(r.artifacts.size(), 1u);
  EXPECT_EQ(r.artifacts[0].name, "points");
  EXPECT_EQ(compare(exact, std::get<PointCloud>(r.artifacts[0].value)).inward, 0u);
  EXPECT_NE(test::invalid_input_message([&] {
              a.run(in, {{"method", std::string("mls")}}, ctx);
            }).find("'method'"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([&] { a.run(Inputs{}, {}, ctx); }).find("'points'"), std::string::npos);
}

}  // namespace
}  // namespace cgview
