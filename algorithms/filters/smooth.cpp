// CGAL_EIGEN3_ENABLED is set by CMake (algorithms/CMakeLists.txt): smooth_shape solves a
// sparse system with Eigen.
#include "filters/smooth.h"

#include <CGAL/Polygon_mesh_processing/angle_and_area_smoothing.h>
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {

namespace PMP = CGAL::Polygon_mesh_processing;

SmoothResult smooth(const Mesh& mesh, const SmoothParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("smooth needs a mesh with faces");
  ctx.progress(0, "converting");
  SmoothResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "smooth", p.repair, result.warnings);
  for (int i = 0; i < p.iterations; ++i) {
    ctx.check_cancelled();
    ctx.progress(double(i) / double(p.iterations), "iteration " + std::to_string(i + 1));
    if (p.method == SmoothMethod::mean_curvature_flow)
      PMP::smooth_shape(sm, p.time, CGAL::parameters::number_of_iterations(1));
    else PMP::angle_and_area_smoothing(sm, CGAL::parameters::number_of_iterations(1).use_area_smoothing(false));
  }
  sm.collect_garbage();
  result.mesh = from_surface_mesh(sm);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(smooth, smooth,
                         {.title = "Smooth",
                          .description = "Smooths a manifold triangle mesh by mean curvature flow, or improves "
                                         "its triangles' angles by tangential smoothing and Delaunay flips.",
                          .area = "filters"})

}  // namespace cgview
