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
#include "non_manifold_shapes.h"
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

TEST(GeodesicDistanceTest, NonManifoldInputIsInvalidWithRepairOff) {
  try {
    geodesic_distance(test::non_manifold(), {.repair = false});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("manifold"), std::string::npos) << e.what();
  }
}

// Two spheres touching at a pole (one vertex, a bow-tie): repaired by
// default, the pole split in two, each copy a source; each sphere's
// distances are its own great-circle distances from the pole.
TEST(GeodesicDistanceTest, NonManifoldInputIsRepairedFirstByDefault) {
  EXPECT_TRUE(GeodesicDistanceParams{}.repair);
  const Mesh broken = test::two_spheres_touching(64, 128);
  ASSERT_EQ(broken.positions[0], (Vec3{0, 0, 1}));  // the pole they share
  const Mesh before = broken;
  const GeodesicDistanceResult r = geodesic_distance(broken, {.sources = "0"});
  test::expect_same_mesh(broken, before);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("geodesic_distance: the mesh was not manifold", 0), 0u) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("a copy was repaired first: 1 vertex duplicated"), std::string::npos) << r.warnings[0];
  const ScalarField& f = r.distance;
  ASSERT_EQ(f.values.size(), broken.num_vertices());
  EXPECT_NEAR(f.values[0], 0.0, 1e-3);
  std::vector<double> errors[2];
  for (std::size_t i = 0; i < broken.num_vertices(); ++i) {
    const double z = broken.positions[i].z;
    const bool upper = z > 1;  // the shared pole (z = 1) is the lower sphere's
    const double exact = std::acos(std::clamp(upper ? 2 - z : z, -1.0, 1.0));
    if (exact > 0.3) errors[upper].push_back(std::abs(double(f.values[i]) - exact) / exact);
  }
  for (const std::vector<double>& e : errors) {
    ASSERT_GT(e.size(), 1000u);
    EXPECT_LT(percentile(e, 0.5), 0.05);
    EXPECT_LT(percentile(e, 0.95), 0.05);
  }
  // With repair off: refused, as before.
  try {
    geodesic_distance(broken, {.sources = "0", .repair = false});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("geodesic_distance needs a manifold mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("set 'repair'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cgview
