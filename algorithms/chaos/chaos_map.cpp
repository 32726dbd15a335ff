// chaos_map: a chaotic map (Ikeda, Arnold's cat, logistic, Henon, or a 3D
// composition) applied `steps` times to the normalized vertex positions,
// as in the CGView paper's Figure 11 (the Ikeda map on the bunny).
#include <string>

#include "chaos/chaos_params.h"
#include "chaos/maps.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params : chaos::MapParamFields {
  int steps = 1;
  template <class V>
  void describe(V& v) {
    describe_map(v);
    v.integer("steps", steps, {.label = "Steps", .min = 0, .max = 1000, .help = "how many times the map is applied"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_vertices() == 0) throw InvalidInput("chaos_map: the mesh has no vertices");
  const chaos::MapParams mp = p.map_params();
  ctx.progress(0, "mapping");
  const chaos::MapResult r = chaos::apply_map(mesh.positions, mp, p.steps, [&](int k) {
    ctx.check_cancelled();
    ctx.progress(double(k) / p.steps, "mapping");
  });
  ctx.check_cancelled();
  AlgorithmResult result;
  Mesh out = mesh;
  out.positions = r.positions;
  // Normals no longer describe the moved surface.
  out.normals.clear();
  out.normal_faces.clear();
  if (r.escaped > 0)
    result.warnings.push_back(std::to_string(r.escaped) +
                              " vertices left every bound (|coordinate| > 1e6, outside the map's basin) and were "
                              "frozen at their last finite position");
  result.artifacts.push_back({"mesh", std::move(out)});
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(chaos_map, Params, run,
                          {.title = "Chaotic map (Ikeda, cat, logistic, Henon, composite)",
                           .description = "Applies a chaotic map `steps` times to the vertex positions, normalized "
                                          "to the bounding box (the CGView paper's Figure 11). Teaching code: see "
                                          "docs/CHAOS.md.",
                           .area = "chaos",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
