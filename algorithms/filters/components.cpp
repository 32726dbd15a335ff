#include "filters/components.h"

#include <CGAL/Polygon_mesh_processing/connected_components.h>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {

ComponentsResult components(const Mesh& mesh, const ComponentsParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("components needs a triangle mesh: the mesh has no faces");
  mesh.validate();
  ctx.progress(0.0, "halfedges");
  ComponentsResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "components", p.repair, result.warnings);
  ctx.check_cancelled();
  ctx.progress(0.3, "components");
  namespace PMP = CGAL::Polygon_mesh_processing;
  auto component = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:cgview_component").first;
  const std::size_t n = PMP::connected_components(sm, component);
  ctx.check_cancelled();

  std::size_t kept = n;
  if (p.mode == ComponentsMode::count) {
    result.mesh = mesh;
  } else {
    ctx.progress(0.6, "removing");
    if (p.mode == ComponentsMode::keep_largest) kept = n - PMP::keep_largest_connected_components(sm, 1);
    else kept = n - PMP::keep_large_connected_components(sm, std::size_t(p.min_faces));
    sm.collect_garbage();
    result.mesh = from_surface_mesh(sm);
  }
  result.metrics = Metrics{{"components", double(n)}, {"kept", double(kept)}};
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(components, components,
                         {.title = "Connected components",
                          .description = "Connected components of the faces (CGAL Polygon Mesh Processing): count "
                                         "them, keep the largest, or drop those with fewer faces than a threshold.",
                          .area = "filters"})

}  // namespace cgview
