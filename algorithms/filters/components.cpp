// components: connected components of the faces (CGAL Polygon Mesh
// Processing's connected_components): count them, keep the largest, or drop
// the small ones.
#include <string>
#include <vector>

#include <CGAL/Polygon_mesh_processing/connected_components.h>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  bool repair = false;
  std::string mode = "keep_largest";
  int min_faces = 100;
  template <class V>
  void describe(V& v) {
    v.choice("mode", mode,
             {.label = "Mode",
              .help = "keep_largest: the component with the most faces; drop_smaller_than: remove components with "
                      "fewer than min_faces faces; count: only count them (the mesh comes back unchanged)",
              .choices = {"keep_largest", "drop_smaller_than", "count"}});
    v.integer("min_faces", min_faces,
              {.label = "Minimum faces",
               .min = 1,
               .max = 1e9,
               .help = "for drop_smaller_than: the smallest size kept",
               .when = {"mode", {"drop_smaller_than"}}});
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("components needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  ctx.progress(0.0, "halfedges");
  AlgorithmResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "components", p.repair, result.warnings);
  ctx.check_cancelled();
  ctx.progress(0.3, "components");
  namespace PMP = CGAL::Polygon_mesh_processing;
  auto component = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:cgview_component").first;
  const std::size_t n = PMP::connected_components(sm, component);
  ctx.check_cancelled();

  std::size_t kept = n;
  Mesh out;
  if (p.mode == "count") {
    out = mesh;
  } else {
    ctx.progress(0.6, "removing");
    if (p.mode == "keep_largest") kept = n - PMP::keep_largest_connected_components(sm, 1);
    else kept = n - PMP::keep_large_connected_components(sm, std::size_t(p.min_faces));
    sm.collect_garbage();
    out = from_surface_mesh(sm);
  }
  result.artifacts.push_back({"mesh", std::move(out)});
  result.artifacts.push_back({"metrics", Metrics{{"components", double(n)}, {"kept", double(kept)}}});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(components, Params, run,
                          {.title = "Connected components",
                           .description = "Connected components of the faces (CGAL Polygon Mesh Processing): count "
                                          "them, keep the largest, or drop those with fewer faces than a threshold.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
