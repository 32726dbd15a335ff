// sdf_fast: the accelerated SDF (sdf/sdf_fast.h) as a registered algorithm;
// with `compare`, also the full SDF and the error map of the paper's Figure 9.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "sdf/sdf_fast.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {
namespace {

struct Params : SdfParamFields {
  double fraction = 0.1;
  std::string solver = "conjugate_gradient";
  double curvature_weight = 0.0;
  bool compare = false;
  template <class V>
  void describe(V& v) {
    v.number("fraction", fraction,
             {.label = "Fraction of faces",
              .min = 1e-6,
              .max = 1,
              .help = "the share of faces whose SDF is cast by rays, in (0, 1]"});
    v.choice("solver", solver,
             {.label = "Solver",
              .help = "conjugate_gradient (from each face's nearest sample) or cholesky (sparse LDLT), both Eigen's",
              .choices = {"conjugate_gradient", "cholesky"},
              .advanced = true});
    v.number(
        "curvature_weight", curvature_weight,
        {.label = "Curvature guidance",
         .min = -100,
         .max = 100,
         .help = "weight of the faces' negative mean curvature in the Poisson equation (0: harmonic interpolation)",
         .advanced = true});
    v.boolean("compare", compare,
              {.label = "Compare with the full SDF", .help = "also compute the SDF on every face, and the error map"});
    describe_sdf(v);
  }
};

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (!(p.fraction > 0)) throw InvalidInput("parameter 'fraction' must be above 0");
  const auto t0 = std::chrono::steady_clock::now();
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  FastOptions fast;
  fast.fraction = p.fraction;
  fast.solver = p.solver == "cholesky" ? Solver::cholesky : Solver::conjugate_gradient;
  fast.curvature_weight = p.curvature_weight;
  fast.smooth = p.smooth;
  fast.window = p.window;
  FastSdf approx = sdf_fast(mesh, graph, p.options(), fast, &ctx);
  AlgorithmResult result;
  warn_missing(approx.raw, result.warnings);
  const double fast_seconds = seconds_since(t0);
  Metrics m{{"faces", double(mesh.faces.size())},
            {"samples", double(approx.samples.size())},
            {"unknowns", double(approx.unknowns)},
            {"iterations", double(approx.iterations)},
            {"seconds", fast_seconds}};
  result.artifacts.push_back(
      {"sdf_fast",
       ScalarField{"sdf_fast", Location::face, ColorHint::standard, {approx.values.begin(), approx.values.end()}}});
  if (p.compare) {
    const auto t1 = std::chrono::steady_clock::now();
    RawSdf full = raw_sdf(mesh, p.options(), {}, &ctx, 0.0, 0.9);
    postprocess(mesh, graph, full.values, p, ctx);
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
    result.artifacts.push_back(
        {"sdf", ScalarField{"sdf", Location::face, ColorHint::standard, {full.values.begin(), full.values.end()}}});
    result.artifacts.push_back({"error", ScalarField{"error", Location::face, ColorHint::magnitude, std::move(error)}});
  }
  result.artifacts.push_back({"metrics", std::move(m)});
  ctx.progress(1.0, "done");
  return result;
}

}  // namespace
}  // namespace cgview::sdf

CGVIEW_REGISTER_ALGORITHM(
    sdf_fast, cgview::sdf::Params, cgview::sdf::run,
    {.title = "Accelerated SDF (Poisson)",
     .description = "The SDF cast on a fraction of the faces, spread over the surface, and propagated "
                    "to the others by a Poisson equation on the dual graph (the CGView paper, 3.2); "
                    "with compare, the full SDF and the error map beside it.",
     .area = "sdf",
     .outputs = {{"sdf_fast", cgview::OutputKind::scalar_field},
                 {"sdf", cgview::OutputKind::scalar_field},
                 {"error", cgview::OutputKind::scalar_field},
                 {"metrics", cgview::OutputKind::metrics}},
     .inputs = {cgview::sdf::kSdfInput}});
