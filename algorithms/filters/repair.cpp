// repair: cleans a triangle soup and rebuilds a manifold mesh from it, with
// CGAL's polygon soup tools (filters/repair_mesh.h), with a report of what
// changed.  It works on the soup, so it accepts what no halfedge structure can
// hold (three faces on an edge, a bowtie vertex); a closed result facing
// inward is turned outward (core/orient.h) unless asked not to.
#include <string>

#include "core/mesh_report.h"
#include "core/orient.h"
#include "filters/repair_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  bool stitch = true;
  bool outward = true;
  template <class V>
  void describe(V& v) {
    v.boolean("stitch", stitch, {.label = "Stitch borders", .help = "glue border edges whose end points coincide"});
    v.boolean("outward", outward,
              {.label = "Orient outward", .help = "turn a closed mesh whose faces all face inward outward"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("repair needs a mesh with faces");
  ctx.progress(0, "checking");
  const MeshReport before = mesh_report(mesh);
  ctx.progress(0.1, "repairing");
  RepairReport rep;
  SurfaceMesh sm = repair_to_surface_mesh(mesh, p.stitch, rep);
  ctx.check_cancelled();
  Mesh out = from_surface_mesh(sm);
  const bool turned = p.outward && orient_outward(out);
  const MeshReport after = mesh_report(out);

  AlgorithmResult result;
  result.artifacts.push_back({"mesh", std::move(out)});
  result.artifacts.push_back({"metrics", Metrics{
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
                                         }});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(repair, Params, run,
                          {.title = "Repair (soup clean-up, orient, stitch)",
                           .description = "Merges duplicate points, removes degenerate and duplicate faces and "
                                          "isolated points, splits non-manifold edges and vertices so the faces "
                                          "can be oriented, then stitches coinciding borders, and turns a closed "
                                          "mesh facing inward outward. Accepts non-manifold input.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
