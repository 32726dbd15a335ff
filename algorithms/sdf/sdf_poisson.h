// The accelerated SDF (CGView paper, section 3.2): the SDF computed by rays on
// a well-spread fraction of the faces only, and propagated to the others by a
// Poisson equation on the dual graph (faces as nodes, shared edges as arcs):
//
//   for each face p without rays,
//     sum_{q ~ p} (f(p) - f(q)) = -lambda kappa(p),
//
// the sampled faces' values being Dirichlet conditions (their terms move to
// the right-hand side).  kappa(p) is the face's curvature, the mean of its
// vertices' mean curvature (filters/vertex_curvatures.h), as the paper's guidance
// field; lambda = curvature_weight * l^2, with l the mean distance between
// adjacent face centroids, keeps the equation's two sides in the same units
// (a length) whatever the mesh's scale and density.
//
// The samples come in two rounds of rays on one BVH: 60% spread evenly
// over the faces (spread_samples), then 40% where those leave the SDF least
// certain, that is where the values of the samples around a face disagree
// most, kept apart by their rings from the samples so far.  The full SDF
// is rough at the scale of a few faces on some meshes (mannequin-devil's
// neighbouring faces differ by 3% of its range): there even its own values
// at evenly spread samples, interpolated, are 3.5% off, and samples where
// it varies help more than samples where it does not.  The samples' values
// are then smoothed by the full SDF's filter on a graph of the samples
// (neighbours where their nearest faces touch), its window one ring
// narrower than the full SDF's (the second round's samples lie closer
// together), in hops of the mean rings between neighbours.
//
// Both rounds choose one face after another, each choice walking the rings
// around it: on one core, 0.43 s and 0.09 s of the 1.42M-face mesh's 2.1 s
// on two, and on more cores a larger share.  From 2 kSampleBlockFaces faces
// the mesh is cut into blocks along a Morton curve (sdf/curve_blocks.h),
// each block chooses its share of the samples (by its faces) within itself,
// and the blocks go to every core.  A block's rings stop at its border, so
// both sides of a border choose faces beside it: near borders the samples
// lie closer together (on that mesh, 1.1% of the faces are beside one).
//
// The matrix (the graph Laplacian restricted to the unknown faces) is
// symmetric positive definite when every connected part of the mesh has a
// sampled face, which the sampling guarantees.  Solved exactly with Eigen: a
// sparse Cholesky factorization (SimplicialLDLT), or conjugate gradients
// (Jacobi preconditioner) started from each face's nearest sample's value.
// By default (Solver::diffusion) it is not solved: from each face's nearest
// sample's value, round(0.6 / fraction) Jacobi sweeps (each unknown face
// takes its neighbours' mean, less its guidance term), capped at 256, both
// weighted by the dihedral angles: an arc across a sharp edge, a concave
// one most (where parts meet and the SDF jumps), counts less in the means
// and more in the distances to the nearest sample.  The
// exact solution spreads each sample's value far beyond its neighbourhood,
// where the full SDF has moved on: stopped early, the field is a local
// average of the nearby samples, closer to the full SDF on every mesh
// measured (docs/BENCHMARKS.md) and about ten times cheaper.  Last, with
// smoothing, each sample takes its neighbours' weighted mean, as the faces
// between samples rest on several samples and a sample on its own rays
// alone.
//
// A sample whose rays all escaped (an open mesh) is no boundary value: the
// faces nearer to such a sample than to any other are taken as the region
// without a value it marks, and get what the full SDF's postprocess gives
// such a region (fill_missing, then its bilateral filter's smoothing, here
// window^2 / 6 sweeps of neighbours' means, near the region's border): a
// ramp over a few rings from the smallest value up to the neighbours',
// where the smallest value as a boundary value missed it by 8-10% of the
// range and pulled the thick neighbours down.
//
// What sdf_fast (sdf/sdf_fast.h) runs, without its metrics and comparison:
// for the benchmark and the tests.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "sdf/sdf_fast.h"
#include "sdf/sdf_rays.h"

namespace cgview::sdf {

struct FastSdf {
  std::vector<double> values;          // one per face
  std::vector<std::uint32_t> samples;  // the faces that got rays
  RawSdf raw;                          // their raw values, in the order of `samples`
  std::size_t unknowns = 0;            // faces solved for
  int iterations = 0;                  // diffusion's sweeps, conjugate gradients' iterations (0 for Cholesky)
  Adjacency graph;                     // the face graph, when poisson_sdf built it
  // Each step's wall time in seconds, in order (for the benchmark: which
  // steps a machine's cores or GPU leave to wait on).
  std::vector<std::pair<std::string, double>> steps;
};

// `count` faces spread evenly over the surface by farthest-point sampling in
// rings of `face_graph`: the first face of each connected part, then again
// and again a face the most rings away from all those chosen.  Even in
// faces, not in area: as many samples in a finely meshed finger as in as
// many faces of a coarse torso.  max(count, parts) faces (all when count is
// larger), sorted.
std::vector<std::uint32_t> spread_samples(const Adjacency& face_graph, std::size_t count);

// The faces of a block the samples are chosen in, at least: 2^17, so that
// on the 1.42M-face mesh ten blocks keep ten cores busy, and meshes under
// 262k faces are one block, their samples as chosen on the whole mesh.
inline constexpr std::size_t kSampleBlockFaces = std::size_t(1) << 17;

// The accelerated SDF of every face: `p.fraction` of them cast (with
// `p.sdf`'s rays, their values smoothed among themselves when
// `p.sdf.smooth`), the others solved for with `p.solver`; `p.compare` is
// not looked at.  Throws InvalidInput for parameters outside their ranges
// and what raw_sdf throws.
FastSdf poisson_sdf(const Mesh& mesh, const Adjacency& face_graph, const SdfFastParams& p,
                    const Context* ctx = nullptr);
// The same, with the face graph built on a second thread while the BVH is,
// and left in the result's `graph`.
FastSdf poisson_sdf(const Mesh& mesh, const SdfFastParams& p, const Context* ctx = nullptr);

}  // namespace cgview::sdf
