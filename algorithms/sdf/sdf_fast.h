// The accelerated SDF (CGView paper, section 3.2): the SDF computed by rays on
// a well-spread fraction of the faces only, and propagated to the others by a
// Poisson equation on the dual graph (faces as nodes, shared edges as arcs):
//
//   for each face p without rays,
//     sum_{q ~ p} (f(p) - f(q)) = -lambda kappa(p),
//
// the sampled faces' values being Dirichlet conditions (their terms move to
// the right-hand side).  kappa(p) is the face's curvature, the mean of its
// vertices' mean curvature (filters/curvature.h), as the paper's guidance
// field; lambda = curvature_weight * l^2, with l the mean distance between
// adjacent face centroids, keeps the equation's two sides in the same units
// (a length) whatever the mesh's scale and density.
//
// The matrix (the graph Laplacian restricted to the unknown faces) is
// symmetric positive definite when every connected part of the mesh has a
// sampled face, which the sampling guarantees.  Solved with Eigen: a sparse
// Cholesky factorization (SimplicialLDLT), or conjugate gradients (Jacobi
// preconditioner) started from each face's nearest sample's value.
#pragma once

#include <cstdint>
#include <vector>

#include "sdf/sdf.h"

namespace cgview::sdf {

enum class Solver { cholesky, conjugate_gradient };

struct FastOptions {
  double fraction = 0.1;  // of the faces that get rays, in (0, 1]
  Solver solver = Solver::cholesky;
  double curvature_weight = 0.0;  // lambda / l^2
  // The bilateral filter of the full SDF (sdf.h), applied to the samples
  // before the solve: the solution is as smooth as its boundary values, and
  // filtering 1 face in 10 costs a tenth.
  bool smooth = true;
  int window = 0;
};

struct FastSdf {
  std::vector<double> values;          // one per face (holes filled as fill_missing does)
  std::vector<std::uint32_t> samples;  // the faces that got rays
  RawSdf raw;                          // their raw values, in the order of `samples`
  std::size_t unknowns = 0;            // faces solved for
  int iterations = 0;                  // conjugate gradients' (0 for Cholesky)
};

// `count` faces spread evenly over the surface: every (F / count)-th face
// along the Morton (Z-order) curve through the face centroids, plus one face
// of each connected part (of `face_graph`) that got none.  Sorted.
std::vector<std::uint32_t> spread_samples(const Mesh& mesh, const Adjacency& face_graph, std::size_t count);

// Throws InvalidInput for a fraction outside (0, 1] and what raw_sdf throws.
FastSdf sdf_fast(const Mesh& mesh, const Adjacency& face_graph, const SdfOptions& options, const FastOptions& fast,
                 const Context* ctx = nullptr);

}  // namespace cgview::sdf
