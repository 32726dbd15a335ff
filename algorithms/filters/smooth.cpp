// smooth: mean curvature flow (Desbrun et al. 1999, CGAL's PMP::smooth_shape)
// or angle-based smoothing with Delaunay flips (PMP::angle_and_area_smoothing).
// CGAL_EIGEN3_ENABLED is set for this file by CMake: smooth_shape solves a
// sparse system with Eigen.
#include <CGAL/Polygon_mesh_processing/angle_and_area_smoothing.h>
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>

#include <string>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

struct Params {
  bool repair = false;
  std::string method = "mean_curvature_flow";
  double time = 1e-4;
  int iterations = 5;
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
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("smooth needs a mesh with faces");
  ctx.progress(0, "converting");
  AlgorithmResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "smooth", p.repair, result.warnings);
  for (int i = 0; i < p.iterations; ++i) {
    ctx.check_cancelled();
    ctx.progress(double(i) / double(p.iterations), "iteration " + std::to_string(i + 1));
    if (p.method == "mean_curvature_flow") PMP::smooth_shape(sm, p.time, CGAL::parameters::number_of_iterations(1));
    else PMP::angle_and_area_smoothing(sm, CGAL::parameters::number_of_iterations(1).use_area_smoothing(false));
  }
  sm.collect_garbage();
  result.artifacts.push_back({"mesh", from_surface_mesh(sm)});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(smooth, Params, run,
                          {.title = "Smooth",
                           .description = "Smooths a manifold triangle mesh by mean curvature flow, or improves "
                                          "its triangles' angles by tangential smoothing and Delaunay flips.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
