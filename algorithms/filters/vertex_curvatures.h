// vertex_curvatures: discrete mean and Gaussian curvature at each vertex of a
// triangle mesh (Meyer, Desbrun, Schröder and Barr 2003, "Discrete
// Differential-Geometry Operators for Triangulated 2-Manifolds").
//
//   A_i   the mixed Voronoi area of vertex i (Voronoi in non-obtuse triangles,
//         half or a quarter of the triangle's area in obtuse ones),
//   H_i   = -<L_i, n_i> / 2, where L_i = 1/(2 A_i) sum_j (cot a_ij + cot b_ij)(x_j - x_i)
//         is the cotangent Laplace-Beltrami of the position (= -2 H n), and n_i
//         the angle-weighted vertex normal: positive on a sphere whose faces
//         are counter-clockwise seen from outside (1/r for radius r),
//   K_i   = (2 pi - sum of the angles at i) / A_i, and (pi - sum) / A_i on a
//         border vertex (so that sum_i K_i A_i obeys Gauss-Bonnet with borders).
//
// Border vertices get the same formulas over their one-sided neighbourhood:
// their mean curvature is only indicative.  Degenerate (zero-area) faces are
// left out; a vertex with no area left (isolated, or only on degenerate faces)
// gets 0 for both and is counted in `degenerate_vertices`.
//
// Preconditions: at least one face, and an edge-manifold mesh (no edge shared
// by more than two faces); otherwise throws InvalidInput naming the count.
// Needs no CGAL, so that other algorithms (the SDF) can share it cheaply.
#pragma once

#include <cstddef>
#include <vector>

#include "core/mesh.h"

namespace cgview {

struct VertexCurvatures {
  std::vector<double> mean;      // H, one per vertex
  std::vector<double> gaussian;  // K, one per vertex
  std::vector<double> area;      // the mixed area A_i, one per vertex
  std::size_t degenerate_vertices = 0;
};

VertexCurvatures vertex_curvatures(const Mesh& mesh);

}  // namespace cgview
