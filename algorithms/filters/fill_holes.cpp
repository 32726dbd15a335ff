// CGAL_EIGEN3_ENABLED is set by CMake (algorithms/CMakeLists.txt): fairing solves a sparse
// system with Eigen.
#include "filters/fill_holes.h"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <iterator>
#include <string>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {

namespace PMP = CGAL::Polygon_mesh_processing;

FillHolesResult fill_holes(const Mesh& mesh, const FillHolesParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("fill_holes needs a mesh with faces");
  ctx.progress(0, "converting");
  FillHolesResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "fill_holes", p.repair, result.warnings);
  using Halfedge = SurfaceMesh::Halfedge_index;
  std::vector<Halfedge> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  std::size_t filled = 0, too_large = 0, fairing_failed = 0;
  for (std::size_t i = 0; i < cycles.size(); ++i) {
    ctx.check_cancelled();
    ctx.progress(0.05 + 0.9 * double(i) / double(cycles.size()), "filling holes");
    const Halfedge h = cycles[i];
    if (CGAL::halfedges_around_face(h, sm).size() > std::size_t(p.max_hole_edges)) {
      ++too_large;
      continue;
    }
    std::vector<SurfaceMesh::Face_index> new_faces;
    std::vector<SurfaceMesh::Vertex_index> new_vertices;
    if (p.mode == FillHolesMode::triangulate) {
      PMP::triangulate_hole(sm, h, std::back_inserter(new_faces));
    } else if (p.mode == FillHolesMode::refine) {
      PMP::triangulate_and_refine_hole(sm, h, std::back_inserter(new_faces), std::back_inserter(new_vertices));
    } else {
      const bool faired = std::get<0>(PMP::triangulate_refine_and_fair_hole(sm, h, std::back_inserter(new_faces),
                                                                            std::back_inserter(new_vertices)));
      if (!faired) ++fairing_failed;
    }
    if (!new_faces.empty()) ++filled;
  }
  if (too_large > 0)
    result.warnings.push_back(std::to_string(too_large) + " holes have more than " + std::to_string(p.max_hole_edges) +
                              " edges and were left open");
  if (fairing_failed > 0)
    result.warnings.push_back("fairing failed on " + std::to_string(fairing_failed) +
                              " holes; they are triangulated and refined only");
  if (filled + too_large < cycles.size())
    result.warnings.push_back(std::to_string(cycles.size() - filled - too_large) + " holes could not be triangulated");
  sm.collect_garbage();
  result.mesh = from_surface_mesh(sm);
  result.metrics = Metrics{{"holes_found", double(cycles.size())}, {"holes_filled", double(filled)}};
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(fill_holes, fill_holes,
                         {.title = "Fill holes",
                          .description = "Closes each hole of a manifold triangle mesh up to a size: triangulated, "
                                         "optionally refined and faired.",
                          .area = "filters"})

}  // namespace cgview
