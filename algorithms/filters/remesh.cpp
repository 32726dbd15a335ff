// remesh: isotropic remeshing to a target edge length (Botsch and Kobbelt
// 2004), CGAL's PMP::isotropic_remeshing, one iteration per call.
#include <CGAL/Polygon_mesh_processing/remesh.h>

#include <cmath>
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
  double target_edge_length = 0;
  int iterations = 3;
  template <class V>
  void describe(V& v) {
    v.number("target_edge_length", target_edge_length,
             {.label = "Target edge length",
              .min = 0,
              .help = "the edge length to reach; 0 means the input's mean edge length"});
    v.integer("iterations", iterations,
              {.label = "Iterations", .min = 1, .max = 100, .help = "split/collapse/flip/relax rounds"});
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("remesh needs a mesh with faces");
  ctx.progress(0, "converting");
  AlgorithmResult result;
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
  result.artifacts.push_back({"mesh", from_surface_mesh(sm)});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(remesh, Params, run,
                          {.title = "Isotropic remeshing",
                           .description = "Remeshes a manifold triangle mesh so that its edges approach a target "
                                          "length, by splits, collapses, flips and tangential relaxation.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
