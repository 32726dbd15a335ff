#include "filters/repair.h"

#include <string>

#include "core/mesh_report.h"
#include "core/orient.h"
#include "filters/repair_mesh.h"

namespace cgview {

RepairResult repair(const Mesh& mesh, const RepairParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("repair needs a mesh with faces");
  ctx.progress(0, "checking");
  const MeshReport before = mesh_report(mesh);
  ctx.progress(0.1, "repairing");
  RepairReport rep;
  SurfaceMesh sm = repair_to_surface_mesh(mesh, p.stitch, rep);
  ctx.check_cancelled();
  RepairResult result;
  Mesh& out = result.mesh;
  out = from_surface_mesh(sm);
  const bool turned = p.outward && orient_outward_in_place(out);
  const MeshReport after = mesh_report(out);
  result.metrics = Metrics{
      {"faces_removed", double(rep.faces_removed)},
      {"vertices_merged", double(rep.vertices_merged)},
      {"isolated_vertices_removed", double(rep.isolated_vertices_removed)},
      {"vertices_duplicated", double(rep.vertices_duplicated)},
      {"borders_stitched", double(rep.borders_stitched)},
      {"faces_turned_outward", turned ? double(after.faces) : 0.0},
      {"vertices_before", double(rep.vertices_before)},
      {"vertices_after", double(after.vertices)},
      {"faces_before", double(rep.faces_before)},
      {"faces_after", double(after.faces)},
      {"manifold_before", before.manifold ? 1.0 : 0.0},
      {"manifold_after", after.manifold ? 1.0 : 0.0},
      {"closed_before", before.closed ? 1.0 : 0.0},
      {"closed_after", after.closed ? 1.0 : 0.0},
  };
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(repair, repair,
                         {.title = "Repair (soup clean-up, orient, stitch)",
                          .description = "Merges duplicate points, removes degenerate and duplicate faces and "
                                         "isolated points, splits non-manifold edges and vertices so the faces "
                                         "can be oriented, then stitches coinciding borders, and turns a closed "
                                         "mesh facing inward outward. Accepts non-manifold input.",
                          .area = "filters"})

}  // namespace cgview
