// vertex_curvatures, the helper behind curvature (and the SDF's guidance):
// Gauss-Bonnet holds exactly and a flat grid has none.
#include "filters/vertex_curvatures.h"

#include <gtest/gtest.h>

#include <numbers>

#include "test_support.h"

namespace cgview {
namespace {

TEST(VertexCurvatures, GaussBonnetOnTorusAndSphere) {
  const Mesh t = test::torus(2.0, 0.5, 48, 24);
  const VertexCurvatures ct = vertex_curvatures(t);
  double total = 0, area = 0;
  for (std::size_t v = 0; v < t.num_vertices(); ++v) {
    total += ct.gaussian[v] * ct.area[v];
    area += ct.area[v];
  }
  EXPECT_NEAR(total, 0.0, 1e-9);
  // The mixed areas tile the surface.
  double faces = 0;
  for (double a : face_areas(t)) faces += a;
  EXPECT_NEAR(area, faces, 1e-9 * faces);

  const Mesh s = test::uv_sphere(1.0, 16, 32);
  const VertexCurvatures cs = vertex_curvatures(s);
  total = 0;
  for (std::size_t v = 0; v < s.num_vertices(); ++v) total += cs.gaussian[v] * cs.area[v];
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-9);
}

TEST(VertexCurvatures, FlatGridIsZeroInside) {
  const Mesh g = test::grid(6);
  const VertexCurvatures c = vertex_curvatures(g);
  for (std::size_t v = 0; v < g.num_vertices(); ++v) {
    EXPECT_NEAR(c.mean[v], 0.0, 1e-9);
    const Vec3 p = g.positions[v];
    if (p.x > 0 && p.x < 6 && p.y > 0 && p.y < 6) {
      EXPECT_NEAR(c.gaussian[v], 0.0, 1e-9);
    }
  }
}

}  // namespace
}  // namespace cgview
