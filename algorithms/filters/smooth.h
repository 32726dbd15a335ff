// smooth: mean curvature flow (Desbrun et al. 1999, CGAL's PMP::smooth_shape)
// or angle-based smoothing with Delaunay flips (PMP::angle_and_area_smoothing)
// of a manifold triangle mesh.
//
//   Mesh m = read_mesh("bunny.off");
//   SmoothResult r = smooth(m, {.method = SmoothMethod::angle_and_area, .iterations = 10});
//   write_mesh(r.mesh, "smooth.off");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

enum class SmoothMethod { mean_curvature_flow, angle_and_area };

struct SmoothParams {
  SmoothMethod method = SmoothMethod::mean_curvature_flow;
  double time = 1e-4;
  int iterations = 5;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.choice("method", method,
             {.label = "Method",
              .help = "mean_curvature_flow: shape smoothing, shrinks bumps (uses time); angle_and_area: "
                      "improves triangle angles by moving vertices tangentially and flipping edges, keeping "
                      "the shape (area smoothing needs Ceres, absent here, so only angles are optimized)",
              .choices = {"mean_curvature_flow", "angle_and_area"}});
    v.number("time", time,
             {.label = "Time step",
              .min = 1e-8,
              .max = 1,
              .help = "mean_curvature_flow only: the step of each iteration; larger smooths faster",
              .when = {"method", {"mean_curvature_flow"}}});
    v.integer("iterations", iterations, {.label = "Iterations", .min = 1, .max = 1000});
    describe_repair(v, repair);
  }
};

struct SmoothResult {
  Mesh mesh;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a mesh without faces, or one that is not manifold
// with `repair` off.
SmoothResult smooth(const Mesh& mesh, const SmoothParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
