// fill_holes on the elephant with holes (closed, of the whole elephant's
// genus) and on a grid (one hole: its border).
#include "filters/fill_holes.h"

#include <gtest/gtest.h>

#include <string>

#include "core/mesh_report.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "io/mesh_io.h"
#include "repair_first.h"

namespace cgview {
namespace {

TEST(FillHolesTest, ClosesTheElephant) {
  const Mesh holed = read_mesh(test::sample("elephant-with-holes.off"));
  const Mesh whole = read_mesh(test::sample("elephant.off"));
  ASSERT_GT(mesh_report(holed).boundary_loops, 0u);
  const FillHolesResult r = fill_holes(holed);
  const MeshReport rep = mesh_report(r.mesh);
  EXPECT_EQ(rep.boundary_loops, 0u);
  EXPECT_EQ(rep.genus, mesh_report(whole).genus);
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("holes_found"), double(mesh_report(holed).boundary_loops));
  EXPECT_EQ(m.at("holes_filled"), m.at("holes_found"));
}

TEST(FillHolesTest, TriangulateModeAndSizeLimit) {
  const Mesh g = test::grid(4);  // one hole of 16 edges: the grid's border
  const MeshReport filled = mesh_report(fill_holes(g, {.mode = FillHolesMode::triangulate}).mesh);
  EXPECT_EQ(filled.boundary_loops, 0u);
  const FillHolesResult r = fill_holes(g, {.max_hole_edges = 10});
  EXPECT_EQ(mesh_report(r.mesh).boundary_loops, 1u);
  EXPECT_EQ(r.metrics.at("holes_filled"), 0.0);
  EXPECT_EQ(r.warnings.size(), 1u);
}

TEST(FillHolesTest, NonManifoldInputIsRefused) {
  const std::string what = test::invalid_input_message([] { fill_holes(test::non_manifold(), {.repair = false}); });
  EXPECT_NE(what.find("fill_holes needs a manifold mesh"), std::string::npos) << what;
}

TEST(FillHolesTest, NonManifoldInputIsRepairedFirstByDefault) {
  auto run = [](const Mesh& m, const FillHolesParams& p) { return fill_holes(m, p); };
  test::expect_repaired_by_default<FillHolesParams>("fill_holes", test::sphere_with_a_fin(), run);
  // Two boxes on one edge, each with a face missing away from it: both
  // holes filled, two closed boxes.
  Mesh broken = test::two_boxes_sharing_an_edge();
  const std::size_t first = 0, second = 12 + 7;  // a face of each box (test::box's order) off the shared edge
  broken.faces.erase(broken.faces.begin() + std::ptrdiff_t(second));
  broken.faces.erase(broken.faces.begin() + std::ptrdiff_t(first));
  ASSERT_EQ(mesh_report(broken).boundary_loops, 2u);
  const FillHolesResult r = test::expect_repaired_by_default<FillHolesParams>("fill_holes", broken, run);
  EXPECT_EQ(r.metrics.at("holes_found"), 2.0);
  EXPECT_EQ(r.metrics.at("holes_filled"), 2.0);
  const MeshReport rep = mesh_report(r.mesh);
  EXPECT_TRUE(rep.closed);
  EXPECT_EQ(rep.components, 2u);
}

}  // namespace
}  // namespace cgview
