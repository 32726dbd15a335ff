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
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct CurvatureParams {
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    describe_repair(v, repair);
  }
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

// A mesh with an edge shared by more than two faces is measured on a
// repaired copy (a warning says what changed; a vertex the repair split
// takes the mean of its copies' values), or refused with `repair` off.
// Throws InvalidInput for a mesh without faces.
CurvatureResult curvature(const Mesh& mesh, const CurvatureParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
