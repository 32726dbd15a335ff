// fill_holes: closes holes (border cycles) with CGAL's hole filling (Liepa
// 2003): a minimal-weight triangulation, optionally refined to match the
// surrounding density and faired to blend with it.  CGAL_EIGEN3_ENABLED is set
// for this file by CMake: fairing solves a sparse system with Eigen.
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <iterator>
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
  int max_hole_edges = 1000;
  std::string mode = "refine_and_fair";
  template <class V>
  void describe(V& v) {
    v.integer("max_hole_edges", max_hole_edges,
              {.label = "Largest hole (edges)",
               .min = 3,
               .max = 1e6,
               .help = "holes bounded by more edges than this are left open"});
    v.choice("mode", mode,
             {.label = "Mode",
              .help = "triangulate: fewest new faces; refine: also add vertices to match the surrounding "
                      "density; refine_and_fair: also move them to blend smoothly with the surface",
              .choices = {"triangulate", "refine", "refine_and_fair"}});
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("fill_holes needs a mesh with faces");
  ctx.progress(0, "converting");
  AlgorithmResult result;
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
    if (p.mode == "triangulate") {
      PMP::triangulate_hole(sm, h, std::back_inserter(new_faces));
    } else if (p.mode == "refine") {
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
  result.artifacts.push_back({"mesh", from_surface_mesh(sm)});
  result.artifacts.push_back(
      {"metrics", Metrics{{"holes_found", double(cycles.size())}, {"holes_filled", double(filled)}}});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(fill_holes, Params, run,
                          {.title = "Fill holes",
                           .description = "Closes each hole of a manifold triangle mesh up to a size: triangulated, "
                                          "optionally refined and faired.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
