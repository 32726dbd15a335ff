// hausdorff between shapes at known distances: a box and its translate,
// concentric spheres, a mesh and itself; missing and bad inputs refused.
#include "filters/hausdorff.h"

#include <gtest/gtest.h>

#include <string>

#include "filter_shapes.h"
#include "filters/repair.h"
#include "non_manifold_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

Mesh translated(Mesh m, Vec3 t) {
  for (Vec3& p : m.positions) p = p + t;
  return m;
}

TEST(HausdorffTest, TranslatedBoxIsAtTheTranslation) {
  const Mesh a = test::box();
  const HausdorffResult r = hausdorff(a, translated(a, {0.3, 0, 0}));
  const Metrics& m = r.metrics;
  const double bound = m.at("error_bound");
  EXPECT_NEAR(m.at("hausdorff"), 0.3, bound + 1e-9);
  EXPECT_NEAR(m.at("mesh_to_reference"), 0.3, bound + 1e-9);
  EXPECT_NEAR(m.at("reference_to_mesh"), 0.3, bound + 1e-9);
  // Vertices on x = 0 are 0.3 from the moved box; those on x = 1 lie on it.
  const ScalarField& f = r.distance;
  ASSERT_EQ(f.values.size(), a.num_vertices());
  for (std::size_t i = 0; i < a.num_vertices(); ++i)
    EXPECT_NEAR(f.values[i], a.positions[i].x == 0 ? 0.3 : 0.0, 1e-6) << "vertex " << i;
}

TEST(HausdorffTest, ConcentricSpheresAreTheirRadiusDifferenceApart) {
  const Mesh inner = test::uv_sphere(1.0, 32, 64), outer = test::uv_sphere(1.2, 32, 64);
  const HausdorffResult r = hausdorff(outer, inner);
  const Metrics& m = r.metrics;
  // Faceting moves each surface inward by at most r (1 - cos(pi / 32)) < 0.006.
  EXPECT_NEAR(m.at("hausdorff"), 0.2, 0.006);
  EXPECT_NEAR(m.at("hausdorff_relative"), m.at("hausdorff") / m.at("bbox_diagonal"), 1e-12);
  const ScalarField& f = r.distance;
  const auto [lo, hi] = f.range();
  EXPECT_GT(lo, 0.2 - 1e-6);
  EXPECT_LT(hi, 0.2 + 0.006);
  EXPECT_LE(m.at("vertex_distance_max"), m.at("mesh_to_reference") + m.at("error_bound"));
}

TEST(HausdorffTest, IdenticalMeshesAreAtZero) {
  const Mesh a = test::torus();
  const HausdorffResult r = hausdorff(a, a);
  const Metrics& m = r.metrics;
  EXPECT_LE(m.at("hausdorff"), m.at("error_bound"));
}

TEST(HausdorffTest, MissingOrBadInputsAreInvalid) {
  const Mesh a = test::box();
  // A job names its inputs: the registry refuses one without its reference.
  Context ctx;
  try {
    find_algorithm("hausdorff").run(a, {}, ctx);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("input 'reference' is missing"), std::string::npos) << e.what();
  }
  try {
    hausdorff(test::non_manifold(), a, {.repair = false});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("manifold mesh"), std::string::npos) << e.what();
  }
  try {
    hausdorff(a, Mesh{});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'reference' has no faces"), std::string::npos) << e.what();
  }
  try {
    hausdorff(a, a, {.error_bound = 0.0});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("error_bound"), std::string::npos) << e.what();
  }
}

// Two boxes on one edge, and the same moved up by 0.3: both inputs are
// repaired by default (a warning each), the distance is the translation's,
// as between the repair filter's meshes with repair off.
TEST(HausdorffTest, NonManifoldInputsAreRepairedFirstByDefault) {
  EXPECT_TRUE(HausdorffParams{}.repair);
  const Mesh a = test::two_boxes_sharing_an_edge(), b = translated(a, {0, 0, 0.3});
  const Mesh a_before = a, b_before = b;
  const HausdorffResult r = hausdorff(a, b);
  test::expect_same_mesh(a, a_before);
  test::expect_same_mesh(b, b_before);
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[0].rfind("hausdorff (input 'mesh'): the mesh was not manifold", 0), 0u) << r.warnings[0];
  EXPECT_EQ(r.warnings[1].rfind("hausdorff (input 'reference'): the mesh was not manifold", 0), 0u) << r.warnings[1];
  for (const std::string& w : r.warnings)
    EXPECT_NE(w.find("a copy was repaired first: 2 vertices duplicated"), std::string::npos) << w;
  const Metrics& m = r.metrics;
  const double bound = m.at("error_bound");
  EXPECT_NEAR(m.at("hausdorff"), 0.3, bound + 1e-9);
  const Metrics ref = hausdorff(repair(a).mesh, repair(b).mesh, {.repair = false}).metrics;
  EXPECT_NEAR(m.at("mesh_to_reference"), ref.at("mesh_to_reference"), 2 * bound);
  EXPECT_NEAR(m.at("reference_to_mesh"), ref.at("reference_to_mesh"), 2 * bound);
  // The field stays one value per vertex of the input: 0.3 below, 0 above
  // (on the moved boxes' sides).
  const ScalarField& f = r.distance;
  ASSERT_EQ(f.values.size(), a.num_vertices());
  for (std::size_t i = 0; i < a.num_vertices(); ++i)
    EXPECT_NEAR(f.values[i], a.positions[i].z == 0 ? 0.3 : 0.0, 1e-6) << "vertex " << i;
  // With repair off: the reference is refused too.
  try {
    hausdorff(test::box(), b, {.repair = false});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("hausdorff (input 'reference') needs a manifold mesh"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace cgview
