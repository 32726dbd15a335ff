// The Shape Diameter Function, in one run:
// - sdf against CGAL's sdf_values with the same rays (25, Vogel's spiral,
//   uniform weights), the same cone (120 degrees) and the same
//   post-processing (missing values filled, bilateral filter, linear
//   normalization): time ratio, Pearson r of the normalized values, and
//   the share of faces whose normalized values differ by at most 0.001;
// - sdf_fast at 5%, 10% and 20%, with each solver, against our sdf (same
//   options): the rays it casts as a share of the full SDF's, time ratio,
//   mean and 95th-percentile error relative to the full SDF's range, and
//   the full SDF's own roughness: the mean distance of a face's value from
//   its edge neighbours' mean, in the same units.  sdf_fast's error at 10%
//   is 2.3-2.9 times it on every sample mesh of 20k faces or more: what a
//   field sampled on a tenth of the faces cannot follow is this face-to-face
//   detail (docs/BENCHMARKS.md).  And how far the full SDF moves when the
//   same triangles are listed each from its next corner (as another
//   exporter may write them), in the same units: zero to Embree's float
//   digits, since a face's cone lies in a basis of its normal alone (a cone
//   that turned with the first edge moved it by 0.3-1.4% of the range).
// On the 1M-triangle mesh CGAL runs without post-processing (its bilateral
// filter walks std::maps over ~2000 faces per face: hours), said in the row.
//
// With --steps, sdf_fast's steps at 10% (sdf::FastSdf::steps) under its row.
//
//   build/bin/sdf_bench [--repeat N] [--quick] [--fast-only] [--steps] [--only elephant,...,big,diplodocus,...]
#include <CGAL/mesh_segmentation.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "bench_util.h"
#include "sdf_common.h"
#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"
#include "sdf/sdf_poisson.h"
#include "sdf/sdf_rays.h"

using namespace cgview;

using bench::our_sdf;

namespace {

// The mean |v(f) - mean of v over f's edge neighbours|, over the faces.
double roughness(const Mesh& mesh, const std::vector<double>& v) {
  const Adjacency g = face_neighbors(mesh, edge_topology(mesh));
  double sum = 0;
  for (std::size_t f = 0; f < v.size(); ++f) {
    if (g.degree(f) == 0) continue;
    double mean = 0;
    for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) mean += v[*h];
    sum += std::abs(v[f] - mean / double(g.degree(f)));
  }
  return v.empty() ? 0.0 : sum / double(v.size());
}

sdf::FastSdf our_fast(const Mesh& mesh, const sdf::SdfParams& p, double fraction, sdf::Solver solver) {
  // The face graph built inside, as sdf_fast builds it (beside the BVH).
  return sdf::poisson_sdf(mesh, {.fraction = fraction, .solver = solver, .sdf = p});
}

// The full SDF of the same mesh with each triangle listed from its next
// corner: the same faces, facing the same way.
std::vector<double> turned_sdf(const Mesh& mesh, const sdf::SdfParams& p) {
  Mesh turned = mesh;
  for (Tri& t : turned.faces) t = Tri{t[1], t[2], t[0]};
  return our_sdf(turned, p, true);
}

}  // namespace

int main(int argc, char** argv) {
  // Without CGAL's table (one core, minutes): sdf_fast against our sdf alone,
  // as on a lent GPU machine, where the time is short.
  const bool fast_only = bench::take_option(argc, argv, "--fast-only", false).has_value();
  const bool steps = bench::take_option(argc, argv, "--steps", false).has_value();
  const bench::Options opt = bench::parse_options(argc, argv, "sdf_bench");
  const std::vector<bench::SdfInput> inputs = bench::sdf_inputs(opt, "sdf_bench");
  const sdf::SdfParams defaults;
  std::printf("rays on: %s\n",
              sdf::ray_device(defaults) == sdf::RayDevice::gpu ? "the GPU (a compute shader)" : "Embree");
  if (!fast_only)
    std::printf(
        "sdf against CGAL 5.5 sdf_values (25 rays, 120 degrees, Vogel's spiral, uniform weights, MAD outliers)\n");
  if (!fast_only)
    std::printf("%-18s %9s %10s %10s %8s %9s %9s\n", "mesh", "faces", "CGAL s", "ours s", "ratio", "Pearson", "equal");
  const sdf::SdfParams cgal_like{.weights = sdf::Weights::uniform, .outliers = sdf::Outliers::mad};
  for (const bench::SdfInput& in : fast_only ? std::vector<bench::SdfInput>{} : inputs) {
    const bool big = in.mesh.faces.size() > 500000;
    SurfaceMesh sm = manifold_surface_mesh(in.mesh, "sdf_bench");
    auto map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
    const double cgal_s = bench::best_seconds(
        big ? 1 : opt.repeat, [&] { CGAL::sdf_values(sm, map, 2.0 * std::numbers::pi / 3.0, 25, !big); });
    std::vector<double> ours, theirs;
    const double ours_s = bench::best_seconds(opt.repeat, [&] { ours = our_sdf(in.mesh, cgal_like, !big); });
    if (!big) ours = sdf::normalize_linear(ours);
    for (SurfaceMesh::Face_index f : sm.faces()) theirs.push_back(map[f]);
    // Without post-processing (big) the values are lengths: compared as
    // shares of CGAL's range.
    const auto [lo, hi] = std::minmax_element(theirs.begin(), theirs.end());
    const double unit = big ? *hi - *lo : 1.0;
    std::size_t equal = 0;
    for (std::size_t f = 0; f < theirs.size(); ++f) equal += std::abs(ours[f] - theirs[f]) <= 1e-3 * unit;
    std::printf("%-18s %9zu %10.3f %10.3f %7.1fx %9.4f %8.2f%%%s\n", in.name.c_str(), in.mesh.faces.size(), cgal_s,
                ours_s, cgal_s / ours_s, sdf::pearson(ours, theirs), 100.0 * double(equal) / double(theirs.size()),
                big ? "  (both without post-processing)" : "");
    std::fflush(stdout);
  }

  std::printf("\nsdf_fast against our sdf (defaults: inverse-angle weights, std-dev outliers, bilateral filter)\n");
  std::printf("%-18s %9s %9s %7s %10s %10s %8s %10s %10s %10s %10s\n", "mesh", "fraction", "solver", "rays", "sdf s",
              "fast s", "ratio", "mean err", "p95 err", "sdf rough", "sdf turned");
  const char* const solver_names[] = {"diffusion", "cg", "cholesky"};  // in sdf::Solver's order
  for (const bench::SdfInput& in : inputs) {
    std::vector<double> full;
    const double full_s = bench::best_seconds(opt.repeat, [&] { full = our_sdf(in.mesh, defaults, true); });
    const auto [lo, hi] = std::minmax_element(full.begin(), full.end());
    const double range = *hi - *lo;
    const double rough = roughness(in.mesh, full);
    const std::vector<double> turned = turned_sdf(in.mesh, defaults);
    double moved = 0;
    for (std::size_t f = 0; f < full.size(); ++f) moved += std::abs(turned[f] - full[f]);
    moved /= double(full.size());
    for (double fraction : {0.05, 0.1, 0.2})
      for (sdf::Solver solver : {sdf::Solver::diffusion, sdf::Solver::conjugate_gradient, sdf::Solver::cholesky}) {
        sdf::FastSdf fast;
        const double fast_s =
            bench::best_seconds(opt.repeat, [&] { fast = our_fast(in.mesh, defaults, fraction, solver); });
        std::vector<double> err(full.size());
        double mean = 0;
        for (std::size_t f = 0; f < full.size(); ++f) mean += (err[f] = std::abs(fast.values[f] - full[f]));
        mean /= double(full.size());
        std::sort(err.begin(), err.end());
        const double p95 = err[std::size_t(0.95 * double(err.size() - 1))];
        // The rays cast, as a share of the full SDF's (defaults.rays on every face).
        const double rays = double(fast.raw.rays_cast) / (double(defaults.rays) * double(in.mesh.faces.size()));
        std::printf("%-18s %8.0f%% %9s %6.2f%% %10.3f %10.3f %7.1fx %9.2f%% %9.2f%% %9.2f%% %9.2f%%\n", in.name.c_str(),
                    100 * fraction, solver_names[int(solver)], 100 * rays, full_s, fast_s, full_s / fast_s,
                    100 * mean / range, 100 * p95 / range, 100 * rough / range, 100 * moved / range);
        if (steps && fraction == 0.1 && solver == sdf::Solver::diffusion) {
          std::printf("%-18s   its steps (the last run), ms:", "");
          for (const auto& [name, seconds] : fast.steps) std::printf(" %s %.1f;", name.c_str(), 1e3 * seconds);
          std::printf("\n");
        }
        std::fflush(stdout);
      }
  }
  return 0;
}
