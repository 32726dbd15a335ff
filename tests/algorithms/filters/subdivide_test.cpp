// subdivide: each scheme's face count, and a closed box stays closed.
#include "filters/subdivide.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "filter_shapes.h"
#include "invalid_input.h"
#include "repair_first.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(Subdivide, LoopOnBoxQuadruplesFacesAndStaysClosed) {
  const Mesh b = test::box();
  for (int it = 1; it <= 3; ++it) {
    const Mesh out = subdivide(b, {.method = SubdivideMethod::loop, .iterations = it}).mesh;
    EXPECT_EQ(out.num_faces(), b.num_faces() * std::size_t(std::pow(4, it)));
    EXPECT_TRUE(test::closed(out));
  }
}

TEST(Subdivide, CatmullClarkAndSqrt3) {
  const Mesh b = test::box();
  const Mesh cc = subdivide(b, {.method = SubdivideMethod::catmull_clark}).mesh;
  EXPECT_EQ(cc.num_faces(), 12u * 3 * 2);
  EXPECT_TRUE(test::closed(cc));
  const Mesh s3 = subdivide(b, {.method = SubdivideMethod::sqrt3, .iterations = 2}).mesh;
  EXPECT_EQ(s3.num_faces(), 12u * 9);
  EXPECT_TRUE(test::closed(s3));
}

TEST(Subdivide, BadInputIsRefused) {
  EXPECT_NE(test::invalid_input_message([] {
              subdivide(test::non_manifold(), {.repair = false});
            }).find("1 faces could not be placed in a halfedge structure"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([] { subdivide(test::box(), {.iterations = 6}); }).find("iterations"),
            std::string::npos);
  const Mesh big = test::uv_sphere(1.0, 200, 400);  // ~160k faces, x4^5 > the limit
  EXPECT_NE(test::invalid_input_message([&] { subdivide(big, {.iterations = 5}); }).find("limit"), std::string::npos);
}

TEST(Subdivide, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const SubdivideParams& p) { return subdivide(m, p); };
  test::expect_repaired_by_default<SubdivideParams>("subdivide", test::sphere_with_a_fin(), run);
  // Two boxes on one edge: Loop's four faces for one on each closed box.
  const Mesh broken = test::two_boxes_sharing_an_edge();
  const SubdivideResult r =
      test::expect_repaired_by_default<SubdivideParams>("subdivide", broken, [](const Mesh& m, SubdivideParams p) {
        p.method = SubdivideMethod::loop;
        return subdivide(m, p);
      });
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("2 vertices duplicated"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.mesh.num_faces(), 4 * broken.num_faces());
  EXPECT_EQ(mesh_report(r.mesh).components, 2u);
  EXPECT_TRUE(test::closed(r.mesh));
}

TEST(Subdivide, ProgressIsReportedAndCancellationHonoured) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
  subdivide(test::box(), {}, &ctx);
  EXPECT_EQ(last, 1.0);
  Context cancelled(nullptr, [] { return true; });
  EXPECT_THROW(subdivide(test::box(), {}, &cancelled), Cancelled);
}

TEST(Subdivide, RegisteredInTheFiltersArea) { EXPECT_EQ(find_algorithm("subdivide").info.area, "filters"); }

}  // namespace
}  // namespace cgview
