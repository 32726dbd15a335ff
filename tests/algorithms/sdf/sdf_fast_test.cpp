// sdf_fast: the accelerated SDF against the full one (the paper's Figure 9),
// on thin parts, a mesh facing inward, bad input.
#include "sdf/sdf_fast.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "io/mesh_io.h"
#include "test_support.h"
#include "turned_outward.h"

namespace cgview {
namespace {

// The paper's Figure 9: 10% of the faces cast rays, the rest is solved for.
// The bounds are those bench/sdf_bench reports for these meshes, rounded up
// (docs/BENCHMARKS.md: elephant 3.54% mean, 12.4% p95; armadillo 1.83%, 6.56%),
// as fractions of the full SDF's range.
TEST(SdfFast, TenPercentStaysWithinTheBenchmarksErrorBounds) {
  for (const auto& [name, mean_bound, p95_bound] :
       {std::tuple{"elephant.off", 0.04, 0.13}, std::tuple{"armadillo.off", 0.025, 0.075}}) {
    const Mesh mesh = read_mesh(test::sample(name));
    for (const auto& [solver, solver_name] : {std::pair{sdf::Solver::diffusion, "diffusion"},
                                              std::pair{sdf::Solver::conjugate_gradient, "conjugate_gradient"},
                                              std::pair{sdf::Solver::cholesky, "cholesky"}}) {
      const sdf::SdfFastResult res = sdf::sdf_fast(mesh, {.fraction = 0.1, .solver = solver, .compare = true});
      const Metrics& m = res.metrics;
      EXPECT_LE(m.at("mean_error"), mean_bound) << name << " " << solver_name;
      EXPECT_LE(m.at("p95_error"), p95_bound) << name << " " << solver_name;
      EXPECT_NEAR(m.at("samples"), 0.1 * double(mesh.faces.size()), 0.01 * double(mesh.faces.size()));
      ASSERT_TRUE(res.error && res.sdf);
      const ScalarField& error = *res.error;
      EXPECT_EQ(error.hint, ColorHint::magnitude);
      EXPECT_EQ(error.values.size(), mesh.faces.size());
      EXPECT_EQ(res.sdf->values.size(), mesh.faces.size());
    }
  }
}

// A ring of square section 1 x 1 (r from 2 to 3) with a fin 0.1 thick and 2
// wide around it: thick and thin parts side by side, the fin a few samples
// wide at 10%.  The full SDF is checked against the shape first: a cone of
// 120 degrees across a slab of thickness h measures between h (the axis) and
// h / cos 60 = 2h (its rim), so the fin's faces lie in [0.1, 0.2] and the
// ring's inner wall, 1 from the outer one, in [1, 2].
Mesh finned_ring() {
  const std::vector<std::pair<double, double>> corners{{2, 0},    {3, 0},    {3, 0.45}, {5, 0.45},
                                                       {5, 0.55}, {3, 0.55}, {3, 1},    {2, 1}};
  std::vector<std::pair<double, double>> section;  // edges of about 0.1
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const auto [r0, z0] = corners[i];
    const auto [r1, z1] = corners[(i + 1) % corners.size()];
    const int steps = std::max(1, int(std::lround(std::hypot(r1 - r0, z1 - z0) / 0.1)));
    for (int j = 0; j < steps; ++j) section.push_back({r0 + (r1 - r0) * j / steps, z0 + (z1 - z0) * j / steps});
  }
  return test::swept(section, 180);
}

TEST(SdfFast, TenPercentOnAShapeWithThinAndThickPartsStaysWithinThreePercentOfTheFullSdf) {
  const Mesh ring = finned_ring();
  ASSERT_GE(ring.faces.size(), 20000u);
  const sdf::SdfFastResult res = sdf::sdf_fast(ring, {.fraction = 0.1, .compare = true});
  ASSERT_TRUE(res.sdf);
  std::vector<double> fin, inner;
  for (std::size_t f = 0; f < ring.faces.size(); ++f) {
    const Tri& t = ring.faces[f];
    const Vec3 c = (ring.positions[t[0]] + ring.positions[t[1]] + ring.positions[t[2]]) / 3.0;
    const double r = std::hypot(c.x, c.y);
    if (r > 3.5 && r < 4.5) fin.push_back(res.sdf->values[f]);
    if (r < 2.05 && c.z > 0.2 && c.z < 0.8) inner.push_back(res.sdf->values[f]);
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  ASSERT_FALSE(fin.empty() || inner.empty());
  EXPECT_GE(median(fin), 0.1);
  EXPECT_LE(median(fin), 0.2);
  EXPECT_GE(median(inner), 1.0);
  EXPECT_LE(median(inner), 2.0);
  const Metrics& m = res.metrics;
  EXPECT_LE(m.at("mean_error"), 0.03);
  // A tenth of the faces, 25 rays each: a tenth of the full SDF's rays.
  EXPECT_NEAR(m.at("samples"), 0.1 * double(ring.faces.size()), 1.0);
}

// An open mesh with horns and fingers a few samples wide, whose full SDF is
// rough at the scale of a few faces and whose rays escape on 5% of the
// faces.  The bounds are bench/sdf_bench's measure, rounded up
// (docs/BENCHMARKS.md: 3.21% mean): 4.47% before the faces nearest the
// samples whose rays escaped were filled as the full SDF fills them, 4.26%
// before the second round of samples where the first disagree, 3.71%
// before the diffusion was weighted by the dihedral angles, 3.32% before
// the samples took their neighbours' mean last.  Not the 3% the other
// meshes of 20k faces or more keep: its full SDF is 2.7-5.5 times as
// rough as theirs (bench/sdf_bench).
TEST(SdfFast, TenPercentOnMannequinDevilStaysWithinTheBenchmarksErrorBounds) {
  const Mesh mesh = read_mesh(test::sample("mannequin-devil.off"));
  const sdf::SdfFastResult res = sdf::sdf_fast(mesh, {.fraction = 0.1, .compare = true});
  EXPECT_LE(res.metrics.at("mean_error"), 0.035);
  EXPECT_LE(res.metrics.at("p95_error"), 0.16);
  EXPECT_TRUE(std::any_of(res.warnings.begin(), res.warnings.end(), [](const std::string& w) {
    return w.find("no ray that found the inside") != std::string::npos &&
           w.find("what the full SDF gives such a region") != std::string::npos;
  })) << "the warning says what the faces without a value take";
}

// An open mesh whose rays escape on a quarter of the faces: there the full
// SDF ramps over a few rings from the smallest value (deep inside such a
// region) up to its neighbours' (fill_missing, then the bilateral filter).
// With the samples that found no inside as boundary values at the smallest
// value, the ramp was missed and the thick faces beside it pulled down:
// 5.30% mean error; filled as the full SDF fills them, 4.51% (4.17% with the
// second round of samples, 3.80% with the diffusion weighted by the dihedral
// angles, 3.73% with the samples settled last, 3.15% with CGAL's rays and
// CGAL's filling of the faces without a value, in the faces' order).
TEST(SdfFast, TenPercentOnAnOpenMeshFillsTheRegionsWithoutRaysAsTheFullSdfDoes) {
  const Mesh mesh = read_mesh(test::sample("polygon_mesh.off"));
  ASSERT_GE(mesh.faces.size(), 20000u);
  const sdf::SdfFastResult res = sdf::sdf_fast(mesh, {.fraction = 0.1, .compare = true});
  ASSERT_TRUE(res.sdf);
  EXPECT_LE(res.metrics.at("mean_error"), 0.035);
  // Not biased low where rays escape: the full SDF's smallest values are
  // not spread over the regions' borders.
  const auto [lo, hi] = std::minmax_element(res.sdf->values.begin(), res.sdf->values.end());
  double signed_sum = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) signed_sum += res.sdf_fast.values[f] - res.sdf->values[f];
  EXPECT_GE(signed_sum / double(mesh.faces.size()) / double(*hi - *lo), -0.005);
}

// The turn is the registry's (InputSpec::outward, kSdfInput): a job's path.
TEST(SdfFast, AMeshFacingInwardIsTurnedOutwardForItsRunAndTheResultSaysSo) {
  test::expect_turned_outward("sdf_fast", "sdf_fast");
}

TEST(SdfFastBadInput, ClearErrors) {
  const Mesh sphere = test::uv_sphere();
  Mesh no_faces;
  no_faces.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(sdf::sdf_fast(no_faces), InvalidInput);
  EXPECT_THROW(sdf::sdf_fast(sphere, {.fraction = 0.0}), InvalidInput);
  EXPECT_THROW(sdf::sdf_fast(sphere, {.fraction = 1.5}), InvalidInput);
}

}  // namespace
}  // namespace cgview
