// sdf_fast: the accelerated SDF (the CGView paper, section 3.2).  The SDF
// (sdf/sdf.h) is cast by rays on a fraction of the faces only (in two
// rounds: spread evenly, then where the first round's values disagree),
// and propagated to the others by a Poisson equation on the dual graph,
// optionally guided by the mean curvature: by default a few of its Jacobi
// sweeps from each face's nearest sample, closer to the full SDF than its
// exact solution (sdf/sdf_poisson.h gives the equation and its solvers).  With `compare`, also the full SDF and the
// error map of the paper's Figure 9.
//
//   Mesh m = read_mesh("armadillo.off");
//   sdf::SdfFastResult r = sdf::sdf_fast(m, {.fraction = 0.05, .compare = true});
//   std::printf("mean error %g of the range\n", r.metrics.at("mean_error"));
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {

// diffusion: the equation's Jacobi iterations from each face's nearest
// sample, stopped early (sdf/sdf_poisson.h says when, and why that is
// closer to the full SDF); conjugate_gradient and cholesky solve it exactly.
enum class Solver { diffusion, conjugate_gradient, cholesky };

struct SdfFastParams {
  double fraction = 0.1;  // of the faces that get rays
  Solver solver = Solver::diffusion;
  double curvature_weight = 0.0;  // lambda / l^2
  bool compare = false;
  // The rays, and the bilateral filter of the full SDF, applied to the
  // samples before the solve: the solution is as smooth as its boundary
  // values, and filtering 1 face in 10 costs a tenth.
  SdfParams sdf{};
  template <class V>
  void describe(V& v) {
    v.number("fraction", fraction,
             {.label = "Fraction of faces",
              .min = 1e-6,
              .max = 1,
              .help = "the share of faces whose SDF is cast by rays, in (0, 1]"});
    v.choice("solver", solver,
             {.label = "Solver",
              .help = "diffusion (Jacobi sweeps from each face's nearest sample, stopped early: the closest to the "
                      "full SDF), or the exact solution by conjugate_gradient or cholesky (sparse LDLT), both Eigen's",
              .choices = {"diffusion", "conjugate_gradient", "cholesky"},
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
    sdf.describe(v);
  }
};

struct SdfFastResult {
  ScalarField sdf_fast;              // per face, in the mesh's units
  std::optional<ScalarField> sdf;    // with compare: the full SDF
  std::optional<ScalarField> error;  // with compare: |sdf_fast - sdf| per face
  // faces, samples, unknowns, iterations, seconds; with compare also
  // full_seconds, speedup, and the mean, 95th-percentile and largest error
  // as fractions of the full SDF's range.
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("sdf_fast", sdf_fast);
    v("sdf", sdf);
    v("error", error);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces.
SdfFastResult sdf_fast(const Mesh& mesh, const SdfFastParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview::sdf
