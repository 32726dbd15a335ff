// centroid_distance: the distance of each vertex from the mesh's centroid.
// The template to copy for a new algorithm: this header (parameters, result,
// the function) and centroid_distance.cpp (the function, registered at its
// end); it then appears in `cgview list`, GET /api/v1/algorithms and the
// viewer, and a program calls it directly:
//
//   Mesh m = read_mesh("bunny.off");
//   CentroidDistanceResult r = centroid_distance(m, {.exponent = 2});
//   write_file_bytes("distance.ply", write_ply_with_field(m, r.distance));
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "registry/registry.h"

namespace cgview {

struct CentroidDistanceParams {
  bool normalize = false;  // defaults live here, once
  double exponent = 1.0;
  template <class V>
  void describe(V& v) {
    v.boolean("normalize", normalize, {.label = "Normalize", .help = "divide by the largest distance, giving 0..1"});
    v.number("exponent", exponent,
             {.label = "Exponent", .min = 0.1, .max = 4, .help = "raise each distance to this power"});
  }
};

struct CentroidDistanceResult {
  ScalarField distance;  // per vertex, named "centroid_distance"
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("distance", distance);
  }
};

// Throws InvalidInput for a mesh without vertices, or parameters out of
// their ranges.
CentroidDistanceResult centroid_distance(const Mesh& mesh, const CentroidDistanceParams& p = {},
                                         Context* ctx = nullptr);

}  // namespace cgview
