// sdf: the Shape Diameter Function with CGAL's post-processing; its fields,
// a sphere, open meshes, a mesh facing inward, bad input, cancellation.
#include "sdf/sdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <string_view>

#include "io/mesh_io.h"
#include "sdf/sdf_rays.h"
#include "test_support.h"
#include "turned_outward.h"

namespace cgview {
namespace {

// With the defaults (inverse-angle weights, outliers dropped) every face of
// a sphere agrees with every other: a sphere looks the same from everywhere.
// (sdf_rays_test.cpp: with uniform weights and no outlier removal, the SDF
// is the mean of the rays' chords.)
TEST(Sdf, SphereWithTheDefaultConeIsTheSameOnEveryFace) {
  const double r = 1.5;
  const Mesh sphere = test::uv_sphere(r, 64, 128);
  const ScalarField f = sdf::sdf(sphere, {.smooth = false}).sdf;
  const auto [lo, hi] = f.range();
  EXPECT_LT(hi - lo, 0.02 * hi);
  EXPECT_GT(lo, r);  // between the shortest chord (r, at 60 degrees) and the diameter
  EXPECT_LT(hi, 2 * r);
}

// The turn is the registry's (InputSpec::outward, kSdfInput): a job's path.
TEST(Sdf, AMeshFacingInwardIsTurnedOutwardForItsRunAndTheResultSaysSo) { test::expect_turned_outward("sdf", "sdf"); }

TEST(Sdf, AlgorithmGivesRawNormalizedAndPerVertexFields) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const sdf::SdfResult res = sdf::sdf(mesh);
  const ScalarField& raw = res.sdf;
  const ScalarField& normalized = res.sdf_normalized;
  const ScalarField& per_vertex = res.sdf_vertex;
  EXPECT_EQ(raw.location, Location::face);
  EXPECT_EQ(raw.values.size(), mesh.faces.size());
  EXPECT_EQ(per_vertex.location, Location::vertex);
  EXPECT_EQ(per_vertex.values.size(), mesh.positions.size());
  EXPECT_FLOAT_EQ(normalized.range().first, 0.0f);
  EXPECT_FLOAT_EQ(normalized.range().second, 1.0f);
  // The elephant's legs are thinner than its body: the SDF is in the mesh's units.
  const BBox box = [&] {
    BBox b;
    for (const Vec3& p : mesh.positions) b.add(p);
    return b;
  }();
  EXPECT_LT(raw.range().second, box.diagonal());
  EXPECT_GT(raw.range().first, 0.0f);
  const Metrics& m = res.metrics;
  EXPECT_EQ(m.at("faces"), double(mesh.faces.size()));
}

TEST(SdfBadInput, ClearErrors) {
  const Mesh sphere = test::uv_sphere();
  Mesh no_faces;
  no_faces.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(sdf::sdf(no_faces), InvalidInput);
  EXPECT_THROW(sdf::sdf(sphere, {.rays = 0}), InvalidInput);
  EXPECT_THROW(sdf::sdf(sphere, {.rays = sdf::kMaxRays + 1}), InvalidInput);
  EXPECT_THROW(sdf::sdf(sphere, {.cone_angle = 180.0}), InvalidInput);
}

// Documented behaviour on open meshes: rays that escape through a hole are
// dropped; a face whose rays all escape takes its neighbours' mean (else the
// smallest value) and the result says how many there were.
TEST(SdfBadInput, OpenMeshesGiveValuesAndAWarning) {
  const Mesh open = read_mesh(test::sample("cube-ouvert.off"));
  const sdf::SdfResult res = sdf::sdf(open);
  const ScalarField& f = res.sdf;
  for (float v : f.values) EXPECT_TRUE(std::isfinite(v));
  const sdf::RawSdf raw = sdf::raw_sdf(open, {});
  EXPECT_LT(raw.rays_accepted, raw.rays_cast);
  if (raw.missing) {
    EXPECT_FALSE(res.warnings.empty());
  }
  // A flat sheet: every ray escapes, every face is missing, nothing crashes.
  const Mesh sheet = test::grid(6);
  const sdf::SdfResult flat = sdf::sdf(sheet);
  EXPECT_FALSE(flat.warnings.empty());
  for (float v : flat.sdf.values) EXPECT_EQ(v, 0.0f);
}

TEST(Sdf, CancelsPromptly) {
  const Mesh mesh = read_mesh(test::sample("armadillo.off"));
  int calls = 0;
  Context ctx([&](double, std::string_view) { ++calls; }, [&] { return calls > 2; });
  EXPECT_THROW(sdf::sdf(mesh, {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
