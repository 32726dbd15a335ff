// orient_outward: turns a closed mesh whose faces all face inward (a
// negative volume, a common export error) outward (core/orient.h).  A mesh
// that already faces outward comes back as it was; one with no inside (open,
// non-manifold) too, with a warning that says why.
#include <cmath>
#include <string>

#include "core/mesh_report.h"
#include "core/orient.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  template <class V>
  void describe(V&) {}
};

AlgorithmResult run(const Mesh& mesh, const Params&, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("orient_outward needs a mesh with faces");
  const MeshReport before = mesh_report(mesh);
  Mesh out = mesh;
  const bool flipped = before.faces_inward;  // orient_outward's own test, on the report already made
  if (flipped) flip_faces(out);
  AlgorithmResult result;
  if (!before.closed || !before.oriented)
    result.warnings.push_back(std::string("the mesh has no inside to face (it is ") +
                              (!before.manifold ? "not manifold"
                               : !before.closed ? "open: " + std::to_string(before.boundary_edges) + " boundary edges"
                                                : "inconsistently oriented") +
                              "): it is unchanged; Repair orients and closes what it can");
  result.artifacts.push_back({"mesh", std::move(out)});
  result.artifacts.push_back({"metrics", Metrics{{"faces_flipped", flipped ? double(mesh.num_faces()) : 0.0},
                                                 {"volume_before", before.volume.value_or(0)},
                                                 {"volume_after", before.volume ? std::abs(*before.volume) : 0}}});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(orient_outward, Params, run,
                          {.title = "Orient outward",
                           .description = "Turns a closed mesh whose faces all face inward (a negative volume) "
                                          "outward, face indices kept; any other mesh comes back unchanged.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
