// principal_directions against a torus's analytic curvatures: around the
// tube 1/r, around the axis cos(v) / (R + r cos(v)), the directions at right
// angles; a sphere's are both 1/R.
#include "filters/principal_directions.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(PrincipalDirectionsTest, TorusAgainstItsAnalyticCurvatures) {
  const double R = 2.0, r = 0.5;
  const Mesh torus = test::torus(R, r, 96, 48);
  const PrincipalDirectionsResult res = principal_directions(torus);
  EXPECT_TRUE(res.warnings.empty());
  EXPECT_EQ(res.max_direction.hint, VectorHint::direction);
  EXPECT_EQ(res.max_direction.location, Location::vertex);
  ASSERT_EQ(res.max_direction.values.size(), torus.num_vertices());
  int outer = 0, inner = 0;
  for (std::size_t v = 0; v < torus.num_vertices(); ++v) {
    const Vec3 p = torus.positions[v];
    const double rho = std::hypot(p.x, p.y);
    const double cos_v = (rho - R) / r;  // the angle around the tube, from the outside
    const double k_tube = 1 / r, k_axis = cos_v / (R + r * cos_v);
    EXPECT_NEAR(res.max_curvature.values[v], k_tube, 0.05 * k_tube) << v;
    EXPECT_NEAR(res.min_curvature.values[v], k_axis, 0.05 * k_tube) << v;
    // Along the big circle: the direction of least curvature.
    const Vec3f along{float(-p.y / rho), float(p.x / rho), 0.f};
    const Vec3f d1 = res.max_direction.values[v], d2 = res.min_direction.values[v];
    EXPECT_NEAR(norm(d1), 1.0, 1e-4);
    EXPECT_NEAR(std::abs(dot(d2, along)), 1.0, 0.01) << v;
    EXPECT_NEAR(dot(d1, d2), 0.0, 1e-4);
    if (std::abs(p.z) < 1e-9) (rho > R ? outer : inner)++;
    // On the equators the tube's direction is vertical.
    if (std::abs(p.z) < 1e-9) {
      EXPECT_NEAR(std::abs(d1.z), 1.0, 0.01) << v;
    }
  }
  EXPECT_GT(outer, 0);
  EXPECT_GT(inner, 0);
}

TEST(PrincipalDirectionsTest, SphereBendsAlikeEveryWay) {
  const double R = 3.0;
  const Mesh sphere = test::uv_sphere(R, 48, 96);
  const PrincipalDirectionsResult res = principal_directions(sphere, {.rings = 2, .degree = 3});
  for (std::size_t v = 0; v < sphere.num_vertices(); ++v) {
    if (std::abs(sphere.positions[v].z) > 0.9 * R) continue;  // the poles' fans are not a jet's neighbourhood
    EXPECT_NEAR(res.max_curvature.values[v], 1 / R, 0.03 / R) << v;
    EXPECT_NEAR(res.min_curvature.values[v], 1 / R, 0.03 / R) << v;
  }
}

TEST(PrincipalDirectionsTest, TooSmallANeighbourhoodIsSaidAndLeftWithoutValue) {
  // A lone triangle: three vertices, never the six a quadric needs.
  Mesh tri;
  tri.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tri.faces = {{0, 1, 2}};
  const PrincipalDirectionsResult res = principal_directions(tri);
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_NE(res.warnings[0].find("3 of 3 vertices"), std::string::npos) << res.warnings[0];
  EXPECT_TRUE(std::isnan(res.max_curvature.values[0]));
  EXPECT_TRUE(std::isnan(res.max_direction.values[0].x));
}

TEST(PrincipalDirectionsTest, BadInputIsRefused) {
  EXPECT_NE(test::invalid_input_message([] { principal_directions(Mesh{}); }).find("needs a mesh with faces"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([] {
              principal_directions(test::uv_sphere(), {.rings = 9});
            }).find("parameter 'rings': 9 is over the maximum 4"),
            std::string::npos);
}

TEST(PrincipalDirectionsTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(principal_directions(test::uv_sphere(), {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
