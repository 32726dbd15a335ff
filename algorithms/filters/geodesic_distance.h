// geodesic_distance: approximate geodesic distance from source vertices by the
// heat method (Crane, Weischedel and Wardetzky 2013), CGAL's Heat_method_3 with
// intrinsic Delaunay refinement.
//
//   Mesh m = read_mesh("bunny.off");
//   GeodesicDistanceResult r = geodesic_distance(m, {.sources = "0, 120"});
//   // r.distance.values[v]: the distance of vertex v to the nearer source
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct GeodesicDistanceParams {
  std::string sources = "0";
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.text("sources", sources,
           {.label = "Source vertices", .help = "comma-separated vertex indices the distance is measured from"});
    describe_repair(v, repair);
  }
};

struct GeodesicDistanceResult {
  ScalarField distance;  // per vertex; 0 on vertices used by no face
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("distance", distance);
  }
};

// A mesh that is not manifold is measured as a repaired copy (`repair`, on
// by default: a warning says what changed); the field is still one value
// per vertex of `mesh`, a vertex the repair split taking the least of its
// copies' distances.  Throws InvalidInput for a mesh without faces, one that
// is not manifold with `repair` off, and for sources that are not vertex
// indices, out of range or used by no face.
GeodesicDistanceResult geodesic_distance(const Mesh& mesh, const GeodesicDistanceParams& p = {},
                                         Context* ctx = nullptr);

}  // namespace cgview
