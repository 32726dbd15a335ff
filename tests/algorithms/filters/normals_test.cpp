// normals: unit, outward on a sphere; faces no halfedge structure holds are
// a warning, not an error.
#include "filters/normals.h"

#include <gtest/gtest.h>

#include <string>

#include "filter_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(Normals, SphereNormalsPointOutward) {
  const Mesh m = test::uv_sphere(3.0, 16, 32);
  const Mesh out = normals(m).mesh;
  ASSERT_EQ(out.normals.size(), m.num_vertices());
  EXPECT_TRUE(out.normal_faces.empty());
  EXPECT_EQ(out.faces, m.faces);
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    const Vec3 n = to_double(out.normals[v]);
    EXPECT_NEAR(norm(n), 1.0, 1e-5);
    EXPECT_GT(dot(n, m.positions[v] / norm(m.positions[v])), 0.99);
  }
}

TEST(Normals, NonManifoldFacesAreAWarning) {
  const NormalsResult res = normals(test::non_manifold());
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_NE(res.warnings[0].find("halfedge structure"), std::string::npos);
  EXPECT_EQ(res.mesh.normals.size(), 5u);
}

TEST(Normals, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  normals(test::box(), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(normals(test::box(), {}, &cancelled), Cancelled);
}

TEST(Normals, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("normals").info.area, "filters"); }

}  // namespace
}  // namespace cgview
