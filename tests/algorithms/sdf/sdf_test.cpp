// sdf: the Shape Diameter Function with CGAL's post-processing; its fields,
// a sphere, open meshes, a mesh facing inward, bad input, cancellation.
#include "sdf/sdf.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "cgal_sdf.h"
#include "io/mesh_io.h"
#include "sdf/sdf_rays.h"
#include "test_support.h"
#include "turned_outward.h"

namespace cgview {
namespace {

// With the defaults (inverse-angle weights, rays beyond one standard
// deviation from the median dropped) every face of a sphere is the weighted
// mean of the chords 2 r cos t_i of the cone's rays (tan t_i = (i / n) tan 60
// deg) that the rule keeps.  A chord within 1% of the band's edge is kept
// on some faces and dropped on others (the faceted sphere moves each chord
// by a few parts in ten thousand, and the cone turns with the face's
// normal, as CGAL's), so each face is the mean of one of the bands those
// borderline chords allow, and no other.  (sdf_rays_test.cpp: with uniform
// weights and no outlier removal, the SDF is the mean of the chords.)
TEST(Sdf, SphereWithTheDefaultConeIsTheMeanOfTheChordsItsOutlierRuleKeeps) {
  const double r = 1.5;
  const int n = 25;
  const double half = std::numbers::pi / 3;
  std::vector<double> chord, weight;
  const auto angle = [&](int i) { return std::atan2(std::sin(half) * i / n, std::cos(half)); };
  for (int i = 0; i < n; ++i) {
    chord.push_back(2 * r * std::cos(angle(i)));
    weight.push_back(1.0 / std::max(angle(i), angle(1)));
  }
  std::vector<double> sorted = chord;
  std::sort(sorted.begin(), sorted.end());
  double mean = 0, var = 0;
  for (double c : chord) mean += c / n;
  for (double c : chord) var += (c - mean) * (c - mean) / n;
  const double median = sorted[n / 2], lo = median - std::sqrt(var), hi = median + std::sqrt(var);
  std::vector<int> kept, borderline;
  for (int i = 0; i < n; ++i) {
    if (std::abs(chord[i] - lo) < 0.01 * lo || std::abs(chord[i] - hi) < 0.01 * hi) borderline.push_back(i);
    else if (chord[i] >= lo && chord[i] <= hi) kept.push_back(i);
  }
  ASSERT_LE(borderline.size(), 3u);
  std::vector<double> allowed;
  for (unsigned subset = 0; subset < (1u << borderline.size()); ++subset) {
    std::vector<int> rays = kept;
    for (std::size_t b = 0; b < borderline.size(); ++b)
      if (subset >> b & 1) rays.push_back(borderline[b]);
    double sum = 0, weights = 0;
    for (int i : rays) sum += chord[i] * weight[i], weights += weight[i];
    allowed.push_back(sum / weights);
  }
  const Mesh sphere = test::uv_sphere(r, 64, 128);
  const ScalarField f = sdf::sdf(sphere, {.smooth = false}).sdf;
  ASSERT_EQ(f.values.size(), sphere.faces.size());
  for (std::size_t i = 0; i < f.values.size(); ++i) {
    double nearest = HUGE_VAL;
    for (double a : allowed) nearest = std::min(nearest, std::abs(f.values[i] - a));
    ASSERT_LT(nearest, 0.003 * r) << "face " << i << ": " << f.values[i];
  }
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

// The whole sdf with CGAL's weights and outlier rule is CGAL's sdf_values
// with its post-processing, normalized, on open meshes too: a face whose
// rays all escape takes, as CGAL's check_missing_sdf_values gives it, its
// neighbours' mean as they are when its turn comes in the faces' order (a
// neighbour filled before it counts), else the smallest value.  Every face
// measured equal to 0.001 (mushroom: 686 of 4608 faces without a ray that
// finds the inside; three_peaks: 1351 of 3671); with the neighbours' values
// as they were before the filling, 50% and 20% of the faces were.
TEST(Sdf, IsCgalsSdfValuesWithCgalsRuleOnOpenMeshes) {
  for (const char* name : {"mushroom.off", "three_peaks.off"}) {
    const Mesh mesh = read_mesh(test::sample(name));
    const sdf::SdfResult ours = sdf::sdf(mesh, {.weights = sdf::Weights::uniform, .outliers = sdf::Outliers::mad});
    const std::vector<double> cgal = test::cgal_sdf_values(mesh, 120, 25, true);
    ASSERT_EQ(cgal.size(), mesh.faces.size()) << name;
    std::size_t equal = 0;
    for (std::size_t f = 0; f < cgal.size(); ++f)
      equal += std::abs(double(ours.sdf_normalized.values[f]) - cgal[f]) <= 1e-3;
    std::printf("%s: %zu of %zu faces equal\n", name, equal, mesh.faces.size());
    EXPECT_GE(double(equal), 0.999 * double(mesh.faces.size())) << name;
  }
}

TEST(Sdf, CancelsPromptly) {
  const Mesh mesh = read_mesh(test::sample("armadillo.off"));
  int calls = 0;
  Context ctx([&](double, std::string_view) { ++calls; }, [&] { return calls > 2; });
  EXPECT_THROW(sdf::sdf(mesh, {}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
