#include "filters/subdivide.h"

#include <cmath>

#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/subdivision_method_3.h>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {
namespace {

// Keeps a request from filling the memory: 5 Loop steps on 1M faces is 1G.
constexpr double max_faces = 20e6;

double faces_after(SubdivideMethod method, double faces, int iterations) {
  if (method == SubdivideMethod::loop) return faces * std::pow(4.0, iterations);
  if (method == SubdivideMethod::sqrt3) return faces * std::pow(3.0, iterations);
  return faces * 3 * std::pow(4.0, iterations - 1) * 2;  // quads, triangulated
}

}  // namespace

SubdivideResult subdivide(const Mesh& mesh, const SubdivideParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("subdivide needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  const double expected = faces_after(p.method, double(mesh.num_faces()), p.iterations);
  if (expected > max_faces)
    throw InvalidInput("subdivide would make " + std::to_string(std::llround(expected)) + " faces, over the limit of " +
                       std::to_string(std::llround(max_faces)) + ": use fewer iterations");
  ctx.progress(0.0, "halfedges");
  SubdivideResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "subdivide", p.repair, result.warnings);
  namespace SM = CGAL::Subdivision_method_3;
  const auto one_step = CGAL::parameters::number_of_iterations(1);
  for (int i = 0; i < p.iterations; ++i) {
    ctx.check_cancelled();
    ctx.progress(0.05 + 0.85 * i / p.iterations, "subdivision step " + std::to_string(i + 1));
    if (p.method == SubdivideMethod::loop) SM::Loop_subdivision(sm, one_step);
    else if (p.method == SubdivideMethod::sqrt3) SM::Sqrt3_subdivision(sm, one_step);
    else SM::CatmullClark_subdivision(sm, one_step);
  }
  ctx.check_cancelled();
  if (p.method == SubdivideMethod::catmull_clark) {
    ctx.progress(0.9, "triangulating");
    CGAL::Polygon_mesh_processing::triangulate_faces(sm);
  }
  ctx.progress(0.95, "converting");
  result.mesh = from_surface_mesh(sm);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(subdivide, subdivide,
                         {.title = "Subdivide",
                          .description = "Subdivision surfaces from CGAL's Subdivision_method_3: Loop, Catmull-Clark "
                                         "(triangulated) or sqrt(3). Attributes (normals, UVs, colours) are dropped.",
                          .area = "filters"})

}  // namespace cgview
