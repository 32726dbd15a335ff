// curvature: discrete mean and Gaussian curvature per vertex, the registered
// face of vertex_curvatures() (filters/vertex_curvatures.h, Meyer et al. 2003).
//
//   Mesh m = read_mesh("bunny.off");
//   CurvatureResult r = curvature(m);
//   double h0 = r.mean_curvature.values[0];  // 1/r on a sphere of radius r
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "registry/registry.h"

namespace cgview {

struct CurvatureParams {
  template <class V>
  void describe(V&) {}
};

struct CurvatureResult {
  ScalarField mean_curvature;      // H per vertex, symmetric colours
  ScalarField gaussian_curvature;  // K per vertex, symmetric colours
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mean_curvature", mean_curvature);
    v("gaussian_curvature", gaussian_curvature);
  }
};

// Throws InvalidInput for a mesh without faces or one with an edge shared by
// more than two faces.
CurvatureResult curvature(const Mesh& mesh, const CurvatureParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
