// principal_directions: the directions in which the surface bends most and
// least at each vertex, with those curvatures, from CGAL's local fitting of
// a polynomial (a jet) to the vertex's neighbourhood and its Monge form
// (Cazals and Pouget 2005).  A vector field of directions: a line through
// each vertex, drawn as such by the viewer (Polyscope's vector quantities).
//
//   PrincipalDirectionsResult r = principal_directions(cylinder, {.rings = 2});
//   Vec3f around = r.max_direction.values[0];  // around the axis, 1/r
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "core/vector_field.h"
#include "registry/registry.h"

namespace cgview {

struct PrincipalDirectionsParams {
  int rings = 2;   // the neighbourhood fitted: the vertex and its neighbours this many edges away
  int degree = 2;  // of the fitted polynomial
  template <class V>
  void describe(V& v) {
    v.integer("rings", rings,
              {.label = "Neighbourhood (rings)",
               .min = 1,
               .max = 4,
               .help = "the vertices this many edges away or nearer are fitted; more rings smooth noise"});
    v.integer("degree", degree,
              {.label = "Fitting degree",
               .min = 2,
               .max = 4,
               .help = "of the polynomial fitted to the neighbourhood (2: a quadric); a vertex with fewer than "
                       "(degree + 1)(degree + 2) / 2 neighbours gets no value",
               .advanced = true});
  }
};

struct PrincipalDirectionsResult {
  VectorField max_direction;  // unit, tangent: the direction of most curvature
  VectorField min_direction;  // unit, tangent, at right angles to it
  ScalarField max_curvature;  // k1 >= k2, positive where the surface bends away from its outward normal
  ScalarField min_curvature;  // k2
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("max_direction", max_direction);
    v("min_direction", min_direction);
    v("max_curvature", max_curvature);
    v("min_curvature", min_curvature);
  }
};

// Throws InvalidInput for a mesh without faces.  Vertices whose
// neighbourhood is too small to fit get NaN, and a warning counts them.
PrincipalDirectionsResult principal_directions(const Mesh& mesh, const PrincipalDirectionsParams& p = {},
                                               Context* ctx = nullptr);

}  // namespace cgview
