// geodesic_distance on spheres, against the great-circle distance; bad
// sources and non-manifold meshes are refused.
#include "filters/geodesic_distance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "filter_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::size_t(q * double(v.size() - 1))];
}

TEST(GeodesicDistanceTest, SphereFromNorthPoleMatchesGreatCircle) {
  const Mesh sphere = test::uv_sphere(1.0, 64, 128);
  const GeodesicDistanceResult r = geodesic_distance(sphere, {.sources = "0"});
  const ScalarField& f = r.distance;
  ASSERT_EQ(f.values.size(), sphere.num_vertices());
  EXPECT_EQ(f.location, Location::vertex);
  EXPECT_EQ(f.hint, ColorHint::magnitude);
  EXPECT_NEAR(f.values[0], 0.0, 1e-3);
  std::vector<double> errors;
  for (std::size_t i = 0; i < sphere.num_vertices(); ++i) {
    const double exact = std::acos(std::clamp(sphere.positions[i].z, -1.0, 1.0));
    if (exact > 0.3) errors.push_back(std::abs(double(f.values[i]) - exact) / exact);
  }
  ASSERT_GT(errors.size(), 1000u);
  EXPECT_LT(percentile(errors, 0.5), 0.05);
  EXPECT_LT(percentile(errors, 0.95), 0.05);
}

TEST(GeodesicDistanceTest, TwoSourcesTakeTheNearer) {
  const Mesh sphere = test::uv_sphere(1.0, 32, 64);
  const Index south = Index(sphere.num_vertices() - 1);
  const GeodesicDistanceResult r = geodesic_distance(sphere, {.sources = "0, " + std::to_string(south)});
  const ScalarField& f = r.distance;
  EXPECT_NEAR(f.values[0], 0.0, 0.02);
  EXPECT_NEAR(f.values[south], 0.0, 0.02);
  // The equator is pi/2 from both poles.
  const float max = f.range().second;
  EXPECT_NEAR(max, std::numbers::pi / 2, 0.1);
}

TEST(GeodesicDistanceTest, BadSourcesAreInvalidInput) {
  const Mesh sphere = test::uv_sphere();
  const std::vector<std::string> bads = {"", "x", "1,", "-1", "3.5", std::to_string(sphere.num_vertices())};
  for (const std::string& bad : bads) {
    try {
      geodesic_distance(sphere, {.sources = bad});
      ADD_FAILURE() << "no error for sources '" << bad << "'";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("sources"), std::string::npos) << e.what();
    }
  }
}

TEST(GeodesicDistanceTest, NonManifoldInputIsInvalid) {
  try {
    geodesic_distance(test::non_manifold());
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("manifold"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cgview
