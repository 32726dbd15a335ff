// sample_points: every point on the surface, reproducible by seed.
#include "filters/sample_points.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(SamplePoints, CountAndPointsOnTheSurface) {
  const double r = 1.5;
  const Mesh s = test::uv_sphere(r, 16, 32);
  const Mesh pts = sample_points(s, {.count = 2000}).points;
  ASSERT_EQ(pts.num_vertices(), 2000u);
  EXPECT_EQ(pts.num_faces(), 0u);
  // On the polyhedron, so within the sphere and no deeper than its flattest facet.
  const double inner = r * std::cos(std::numbers::pi / 16);
  for (const Vec3& p : pts.positions) {
    EXPECT_LE(norm(p), r + 1e-9);
    EXPECT_GE(norm(p), inner - 1e-9);
  }
  // On a box every point lies exactly on a face.
  const Mesh onbox = sample_points(test::box(), {.count = 500}).points;
  ASSERT_EQ(onbox.num_vertices(), 500u);
  for (const Vec3& p : onbox.positions) {
    const double d = std::min({p.x, 1 - p.x, p.y, 1 - p.y, p.z, 1 - p.z});
    EXPECT_NEAR(d, 0.0, 1e-12);
    EXPECT_GE(d, -1e-12);
  }
  // The seed makes it reproducible.
  const Mesh again = sample_points(test::box(), {.count = 500}).points;
  EXPECT_EQ(again.positions.front(), onbox.positions.front());
  const Mesh other = sample_points(test::box(), {.count = 500, .seed = 7}).points;
  EXPECT_NE(other.positions.front(), onbox.positions.front());
}

TEST(SamplePoints, NoFacesIsRefused) {
  Mesh points;
  points.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_NE(test::invalid_input_message([&] { sample_points(points); }).find("no faces"), std::string::npos);
}

TEST(SamplePoints, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  sample_points(test::box(), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(sample_points(test::box(), {}, &cancelled), Cancelled);
}

TEST(SamplePoints, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("sample_points").info.area, "filters"); }

}  // namespace
}  // namespace cgview
