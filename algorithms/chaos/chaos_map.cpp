#include "chaos/chaos_map.h"

#include <string>

#include "chaos/maps.h"

namespace cgview {

ChaosMapResult chaos_map(const Mesh& mesh, const ChaosMapParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_vertices() == 0) throw InvalidInput("chaos_map: the mesh has no vertices");
  ctx.progress(0, "mapping");
  const chaos::MapResult r = chaos::apply_map(mesh.positions, p.map, p.steps, [&](int k) {
    ctx.check_cancelled();
    ctx.progress(double(k) / p.steps, "mapping");
  });
  ctx.check_cancelled();
  ChaosMapResult result;
  result.mesh = mesh;
  result.mesh.positions = r.positions;
  // Normals no longer describe the moved surface.
  result.mesh.normals.clear();
  result.mesh.normal_faces.clear();
  if (r.escaped > 0)
    result.warnings.push_back(std::to_string(r.escaped) +
                              " vertices left every bound (|coordinate| > 1e6, outside the map's basin) and were "
                              "frozen at their last finite position");
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_map, chaos_map,
                         {.title = "Chaotic map (Ikeda, cat, logistic, Henon, composite)",
                          .description = "Applies a chaotic map `steps` times to the vertex positions, normalized "
                                         "to the bounding box (the CGView paper's Figure 11). Teaching code: see "
                                         "docs/CHAOS.md.",
                          .area = "chaos"})

}  // namespace cgview
