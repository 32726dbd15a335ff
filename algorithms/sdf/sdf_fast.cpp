#include "sdf/sdf_fast.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "sdf/sdf_poisson.h"

namespace cgview::sdf {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

SdfFastResult sdf_fast(const Mesh& mesh, const SdfFastParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  const auto t0 = std::chrono::steady_clock::now();
  FastSdf approx = poisson_sdf(mesh, p, &ctx);
  const Adjacency& graph = approx.graph;
  SdfFastResult result;
  warn_missing(approx.raw, result.warnings,
               "what the full SDF gives such a region (their neighbours' mean, else the smallest value, then "
               "smoothed), as do the faces nearest them");
  const double fast_seconds = seconds_since(t0);
  Metrics& m = result.metrics;
  m = {{"faces", double(mesh.faces.size())},
       {"samples", double(approx.samples.size())},
       {"unknowns", double(approx.unknowns)},
       {"iterations", double(approx.iterations)},
       {"seconds", fast_seconds}};
  ray_metrics(approx.raw, m);
  result.sdf_fast =
      ScalarField{"sdf_fast", Location::face, ColorHint::standard, {approx.values.begin(), approx.values.end()}};
  if (p.compare) {
    const auto t1 = std::chrono::steady_clock::now();
    RawSdf full = raw_sdf(mesh, p.sdf, {}, &ctx, 0.0, 0.9);
    postprocess(mesh, graph, full.values, p.sdf, ctx);
    m["full_seconds"] = seconds_since(t1);
    m["speedup"] = m["full_seconds"] / std::max(fast_seconds, 1e-9);
    const auto [lo, hi] = std::minmax_element(full.values.begin(), full.values.end());
    const double range = std::max(*hi - *lo, 1e-300);
    std::vector<float> error(full.values.size());
    for (std::size_t f = 0; f < error.size(); ++f) error[f] = float(std::abs(approx.values[f] - full.values[f]));
    std::vector<float> sorted = error;
    std::sort(sorted.begin(), sorted.end());
    double mean = 0;
    for (float e : error) mean += e;
    mean /= double(error.size());
    m["mean_error"] = mean / range;  // fractions of the full SDF's range
    m["p95_error"] = sorted[std::min(sorted.size() - 1, std::size_t(0.95 * double(sorted.size())))] / range;
    m["max_error"] = sorted.back() / range;
    result.sdf = ScalarField{"sdf", Location::face, ColorHint::standard, {full.values.begin(), full.values.end()}};
    result.error = ScalarField{"error", Location::face, ColorHint::magnitude, std::move(error)};
  }
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(sdf_fast, sdf_fast,
                         {.title = "Accelerated SDF (Poisson)",
                          .description = "The SDF cast on a fraction of the faces, spread over the surface, and "
                                         "propagated to the others by a Poisson equation on the dual graph (the "
                                         "CGView paper, 3.2), by default a few of its Jacobi sweeps; with compare, "
                                         "the full SDF and the error map beside it.",
                          .area = "sdf",
                          .inputs = {kSdfInput}})

}  // namespace cgview::sdf
