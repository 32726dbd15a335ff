// The accelerated SDF's steps (sdf/sdf_poisson.h): the samples, the solvers,
// bad input.
#include "sdf/sdf_poisson.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "io/mesh_io.h"
#include "sdf/curve_blocks.h"
#include "sdf/sdf.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(SdfPoisson, SampledFacesKeepTheirRayValuesAndEveryPartGetsOne) {
  const Mesh two = test::merged(test::uv_sphere(1, 16, 32), test::torus(4, 1));
  const Adjacency graph = face_neighbors(two, edge_topology(two));
  const std::vector<std::uint32_t> samples = sdf::spread_samples(graph, 1);
  ASSERT_EQ(samples.size(), 2u);  // one face asked for, one more for the other part
  // Without smoothing, else the samples are filtered among themselves.
  const sdf::FastSdf approx =
      sdf::poisson_sdf(two, graph, {.fraction = 0.05, .solver = sdf::Solver::cholesky, .sdf = {.smooth = false}});
  for (std::size_t i = 0; i < approx.samples.size(); ++i)
    EXPECT_DOUBLE_EQ(approx.values[approx.samples[i]], approx.raw.values[i]);
  for (double v : approx.values) EXPECT_TRUE(std::isfinite(v));
}

TEST(SdfPoisson, BothSolversAgree) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  sdf::SdfFastParams p{.curvature_weight = 1.0};
  p.solver = sdf::Solver::cholesky;
  const sdf::FastSdf a = sdf::poisson_sdf(mesh, graph, p);
  p.solver = sdf::Solver::conjugate_gradient;
  const sdf::FastSdf b = sdf::poisson_sdf(mesh, graph, p);
  EXPECT_GT(b.iterations, 0);
  const auto [lo, hi] = std::minmax_element(a.values.begin(), a.values.end());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) ASSERT_NEAR(a.values[f], b.values[f], 1e-3 * (*hi - *lo));
}

// The default solver's reason to be: the exact solution carries each
// sample's value beyond its neighbourhood, where the full SDF has moved on.
TEST(SdfPoisson, DiffusionStoppedEarlyIsCloserToTheFullSdfThanTheExactSolution) {
  for (const char* name : {"elephant.off", "bear.off"}) {
    const Mesh mesh = read_mesh(test::sample(name));
    const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
    const sdf::SdfResult reference = sdf::sdf(mesh);
    const std::vector<float>& full = reference.sdf.values;
    const auto mean_error = [&](const sdf::FastSdf& a) {
      double sum = 0;
      for (std::size_t f = 0; f < full.size(); ++f) sum += std::abs(a.values[f] - full[f]);
      return sum / double(full.size());
    };
    const sdf::FastSdf early = sdf::poisson_sdf(mesh, graph, {.solver = sdf::Solver::diffusion});
    const sdf::FastSdf exact = sdf::poisson_sdf(mesh, graph, {.solver = sdf::Solver::cholesky});
    EXPECT_EQ(early.iterations, 6) << name;  // round(0.6 / 10%)
    EXPECT_LT(mean_error(early), 0.97 * mean_error(exact)) << name;
  }
}

// sdf_fast's call: the face graph built beside the BVH, and handed back.
TEST(SdfPoisson, BuildingTheFaceGraphItselfGivesTheSameValuesAndHandsTheGraphBack) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  const sdf::FastSdf given = sdf::poisson_sdf(mesh, graph, {});
  const sdf::FastSdf built = sdf::poisson_sdf(mesh, {});
  EXPECT_EQ(built.graph.offsets, graph.offsets);
  EXPECT_EQ(built.graph.items, graph.items);
  EXPECT_TRUE(given.graph.offsets.empty());
  EXPECT_EQ(built.samples, given.samples);
  EXPECT_EQ(built.values, given.values);
}

// The steps' times, for the benchmark: each step once, in order, within the
// call's own time.
TEST(SdfPoisson, ItsStepsAreTimedInOrder) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const auto start = std::chrono::steady_clock::now();
  const sdf::FastSdf fast = sdf::poisson_sdf(mesh, {});
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<std::string> names;
  double sum = 0;
  for (const auto& [name, seconds] : fast.steps) {
    names.push_back(name);
    EXPECT_GE(seconds, 0.0) << name;
    sum += seconds;
  }
  EXPECT_EQ(names, (std::vector<std::string>{"graph, BVH, first samples", "first rays", "second samples", "second rays",
                                             "samples smoothed", "solve", "escaped regions"}));
  EXPECT_LE(sum, total);
}

// From 2 kSampleBlockFaces faces the samples are chosen block by block along
// the curve: each block holds its share of them, and each face gets its own
// part's value (a sphere in a torus of half its thickness), as the rays of
// every 97th face say.
TEST(SdfPoisson, AMeshOfSeveralBlocksHasItsSamplesInEachAndItsValuesRight) {
  const Mesh sphere = test::uv_sphere(1, 256, 256), two = test::merged(sphere, test::torus(4, 0.5, 640, 256));
  const Adjacency graph = face_neighbors(two, edge_topology(two));
  const std::size_t n = graph.size(), split = sphere.faces.size();
  const sdf::CurveBlocks blocks = sdf::curve_blocks(two, graph, sdf::kSampleBlockFaces);
  ASSERT_EQ(blocks.size(), 3u);
  const sdf::FastSdf fast = sdf::poisson_sdf(two, graph, {});
  ASSERT_EQ(fast.samples.size(), std::size_t(std::ceil(0.1 * double(n))));
  EXPECT_TRUE(std::adjacent_find(fast.samples.begin(), fast.samples.end()) == fast.samples.end());
  std::vector<std::size_t> block(n);
  for (std::size_t k = 0; k < blocks.size(); ++k)
    for (std::uint32_t f : blocks.faces[k]) block[f] = k;
  std::vector<double> held(blocks.size(), 0);
  for (std::uint32_t f : fast.samples) ++held[block[f]];
  for (std::size_t k = 0; k < blocks.size(); ++k)  // each round's share rounded
    EXPECT_NEAR(held[k], double(fast.samples.size()) * double(blocks.faces[k].size()) / double(n), 2.0) << k;

  std::vector<std::uint32_t> probes;
  for (std::uint32_t f = 0; f < n; f += 97) probes.push_back(f);
  const sdf::RawSdf rays = sdf::SdfRayCaster(two, {}).cast(probes);
  std::vector<double> ball, tube;
  for (std::size_t i = 0; i < probes.size(); ++i) (probes[i] < split ? ball : tube).push_back(rays.values[i]);
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
    return v[v.size() / 2];
  };
  const double b = median(ball), t = median(tube);
  EXPECT_GT(b, 1.4 * t);
  double worst = 0;
  for (std::size_t f = 0; f < n; ++f) worst = std::max(worst, std::abs(fast.values[f] - (f < split ? b : t)) / t);
  EXPECT_LT(worst, 0.04);  // 0.017 here
}

TEST(SdfPoisson, AFractionOfZeroIsRefused) {
  const Mesh sphere = test::uv_sphere();
  const Adjacency graph = face_neighbors(sphere, edge_topology(sphere));
  try {
    sdf::poisson_sdf(sphere, graph, {.fraction = 0});
    FAIL() << "a fraction of 0 was taken";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("fraction"), std::string::npos);
  }
}

}  // namespace
}  // namespace cgview
