// sdf: the Shape Diameter Function on every face (Shapira, Shamir and
// Cohen-Or 2008; the rays are sdf/sdf_rays.h's), with CGAL's
// post-processing: holes filled, then a bilateral filter.
//
//   Mesh m = read_mesh("elephant.off");
//   sdf::SdfResult r = sdf::sdf(m, {.cone_angle = 90});
//   std::printf("%zu faces, thickest %g\n", r.sdf.values.size(), r.metrics.at("max"));
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {

// SdfParams (sdf/sdf_params.h): the rays, the cone, and the smoothing.

struct SdfResult {
  ScalarField sdf;             // per face, in the mesh's units
  ScalarField sdf_normalized;  // the same, linear to [0, 1]
  ScalarField sdf_vertex;      // per vertex: the mean of its faces'
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("sdf", sdf);
    v("sdf_normalized", sdf_normalized);
    v("sdf_vertex", sdf_vertex);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces.  Rays that escape through a
// hole of an open mesh are dropped, and a warning counts the faces left
// without any.
SdfResult sdf(const Mesh& mesh, const SdfParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview::sdf
