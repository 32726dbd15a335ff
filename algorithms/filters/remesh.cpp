#include "filters/remesh.h"

#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {

namespace PMP = CGAL::Polygon_mesh_processing;

RemeshResult remesh(const Mesh& mesh, const RemeshParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("remesh needs a mesh with faces");
  ctx.progress(0, "converting");
  RemeshResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "remesh", p.repair, result.warnings);
  double target = p.target_edge_length;
  if (target == 0) {
    double sum = 0;
    for (auto e : sm.edges())
      sum +=
          std::sqrt(CGAL::squared_distance(sm.point(sm.source(sm.halfedge(e))), sm.point(sm.target(sm.halfedge(e)))));
    target = sum / double(sm.number_of_edges());
  }
  if (!(target > 0)) throw InvalidInput("remesh needs a mesh with edges of non-zero length");
  for (int i = 0; i < p.iterations; ++i) {
    ctx.check_cancelled();
    ctx.progress(double(i) / double(p.iterations), "iteration " + std::to_string(i + 1));
    PMP::isotropic_remeshing(faces(sm), target, sm, CGAL::parameters::number_of_iterations(1));
  }
  sm.collect_garbage();
  result.mesh = from_surface_mesh(sm);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(remesh, remesh,
                         {.title = "Isotropic remeshing",
                          .description = "Remeshes a manifold triangle mesh so that its edges approach a target "
                                         "length, by splits, collapses, flips and tangential relaxation.",
                          .area = "filters"})

}  // namespace cgview
