// subdivide: CGAL's subdivision surfaces (Subdivision_method_3): Loop,
// Catmull-Clark (its quads triangulated afterwards) and Kobbelt's sqrt(3).
#include <cmath>
#include <string>
#include <vector>

#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/subdivision_method_3.h>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

// Keeps a request from filling the memory: 5 Loop steps on 1M faces is 1G.
constexpr double max_faces = 20e6;

struct Params {
  bool repair = false;
  std::string method = "loop";
  int iterations = 1;
  template <class V>
  void describe(V& v) {
    v.choice("method", method,
             {.label = "Method",
              .help = "loop: smooth, each triangle into 4; catmull_clark: quads, each triangle into 3 "
                      "then each quad into 4 per step, split into 2 triangles each at the end; sqrt3: Kobbelt's "
                      "scheme, each triangle into 3",
              .choices = {"loop", "catmull_clark", "sqrt3"}});
    v.integer("iterations", iterations, {.label = "Iterations", .min = 1, .max = 5, .help = "subdivision steps"});
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

double faces_after(const std::string& method, double faces, int iterations) {
  if (method == "loop") return faces * std::pow(4.0, iterations);
  if (method == "sqrt3") return faces * std::pow(3.0, iterations);
  return faces * 3 * std::pow(4.0, iterations - 1) * 2;  // quads, triangulated
}

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("subdivide needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  const double expected = faces_after(p.method, double(mesh.num_faces()), p.iterations);
  if (expected > max_faces)
    throw InvalidInput("subdivide would make " + std::to_string(std::llround(expected)) + " faces, over the limit of " +
                       std::to_string(std::llround(max_faces)) + ": use fewer iterations");
  ctx.progress(0.0, "halfedges");
  AlgorithmResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "subdivide", p.repair, result.warnings);
  namespace SM = CGAL::Subdivision_method_3;
  const auto one_step = CGAL::parameters::number_of_iterations(1);
  for (int i = 0; i < p.iterations; ++i) {
    ctx.check_cancelled();
    ctx.progress(0.05 + 0.85 * i / p.iterations, "subdivision step " + std::to_string(i + 1));
    if (p.method == "loop") SM::Loop_subdivision(sm, one_step);
    else if (p.method == "sqrt3") SM::Sqrt3_subdivision(sm, one_step);
    else SM::CatmullClark_subdivision(sm, one_step);
  }
  ctx.check_cancelled();
  if (p.method == "catmull_clark") {
    ctx.progress(0.9, "triangulating");
    CGAL::Polygon_mesh_processing::triangulate_faces(sm);
  }
  ctx.progress(0.95, "converting");
  result.artifacts.push_back({"mesh", from_surface_mesh(sm)});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(subdivide, Params, run,
                          {.title = "Subdivide",
                           .description = "Subdivision surfaces from CGAL's Subdivision_method_3: Loop, Catmull-Clark "
                                          "(triangulated) or sqrt(3). Attributes (normals, UVs, colours) are dropped.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
