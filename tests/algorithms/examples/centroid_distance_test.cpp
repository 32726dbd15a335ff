// centroid_distance on shapes whose answers are known: a box's corners are
// all half its diagonal away, a sphere's vertices all at its radius (r^e
// with an exponent e, 1 normalized); a mesh without vertices, or an
// exponent out of its range, is refused.
#include "examples/centroid_distance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "invalid_input.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(CentroidDistance, BoxCornersAreHalfTheDiagonalAway) {
  const Mesh box = test::box({-1, -2, -3}, {3, 2, 1});  // centroid (1, 0, -1), half diagonal sqrt(12)
  const CentroidDistanceResult r = centroid_distance(box);
  EXPECT_EQ(r.distance.name, "centroid_distance");
  EXPECT_EQ(r.distance.location, Location::vertex);
  EXPECT_EQ(r.distance.hint, ColorHint::magnitude);
  ASSERT_EQ(r.distance.values.size(), box.num_vertices());
  for (float v : r.distance.values) EXPECT_NEAR(v, std::sqrt(12.0), 1e-5);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(CentroidDistance, SphereVerticesAreAtTheRadius) {
  for (double radius : {0.5, 1.0, 3.0}) {
    SCOPED_TRACE(radius);
    const Mesh s = test::uv_sphere(radius, 12, 24);
    const ScalarField f = centroid_distance(s).distance;
    ASSERT_EQ(f.values.size(), s.num_vertices());
    for (float v : f.values) EXPECT_NEAR(v, radius, 1e-5 * radius);
  }
}

TEST(CentroidDistance, ExponentApplies) {
  const Mesh s = test::uv_sphere(2.0);
  for (double e : {0.5, 2.0, 3.0}) {
    SCOPED_TRACE(e);
    const ScalarField f = centroid_distance(s, {.exponent = e}).distance;
    for (float v : f.values) EXPECT_NEAR(v, std::pow(2.0, e), 1e-4);
  }
  // Exponent 2: the squared radius.
  for (float v : centroid_distance(s, {.exponent = 2}).distance.values) EXPECT_NEAR(v, 4.0, 1e-4);
}

TEST(CentroidDistance, NormalizeDividesByTheLargest) {
  // A sphere: every distance is the largest, so every value is 1.
  const ScalarField s = centroid_distance(test::uv_sphere(5.0), {.normalize = true}).distance;
  for (float v : s.values) EXPECT_NEAR(v, 1.0, 1e-5);
  // Two boxes side by side, one twice the other's size around the same
  // centre: the small box's corners are at half the largest distance.
  const Mesh two = test::merged(test::box({-1, -1, -1}, {1, 1, 1}), test::box({-2, -2, -2}, {2, 2, 2}));
  const ScalarField f = centroid_distance(two, {.normalize = true}).distance;
  ASSERT_EQ(f.values.size(), 16u);
  for (std::size_t i = 0; i < 8; ++i) EXPECT_NEAR(f.values[i], 0.5, 1e-6);
  for (std::size_t i = 8; i < 16; ++i) EXPECT_NEAR(f.values[i], 1.0, 1e-6);
}

TEST(CentroidDistance, EmptyMeshIsInvalidInput) {
  EXPECT_EQ(test::invalid_input_message([] { centroid_distance(Mesh{}); }), "the mesh has no vertices");
}

// The range lives in describe alone; a direct call is held to it as a job is.
TEST(CentroidDistance, AnExponentOutOfItsRangeIsRefusedByName) {
  EXPECT_EQ(test::invalid_input_message([] { centroid_distance(test::uv_sphere(), {.exponent = 9}); }),
            "parameter 'exponent': 9 is over the maximum 4");
  EXPECT_NE(test::invalid_input_message([] {
              centroid_distance(test::uv_sphere(), {.exponent = 0.05});
            }).find("parameter 'exponent'"),
            std::string::npos);
}

TEST(CentroidDistance, ElephantHasOneValuePerVertex) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  const ScalarField f = centroid_distance(m).distance;
  EXPECT_EQ(f.values.size(), 2775u);
  EXPECT_NO_THROW(f.check_matches(m));
  for (float v : f.values) EXPECT_TRUE(std::isfinite(v) && v >= 0);
}

// Progress from the context given, ending at 1; a cancelled one stops it.
TEST(CentroidDistance, ReportsProgressAndStopsWhenCancelled) {
  std::vector<double> fractions;
  Context ctx([&](double f, std::string_view) { fractions.push_back(f); }, nullptr);
  centroid_distance(test::uv_sphere(), {}, &ctx);
  ASSERT_FALSE(fractions.empty());
  EXPECT_EQ(fractions.back(), 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(centroid_distance(test::uv_sphere(), {}, &cancelled), Cancelled);
}

}  // namespace
}  // namespace cgview
