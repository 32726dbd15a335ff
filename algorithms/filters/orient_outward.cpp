#include "filters/orient_outward.h"

#include <cmath>
#include <string>

#include "core/mesh_report.h"
#include "core/orient.h"

namespace cgview {

OrientOutwardResult orient_outward(const Mesh& mesh, const OrientOutwardParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("orient_outward needs a mesh with faces");
  const MeshReport before = mesh_report(mesh);
  OrientOutwardResult result;
  result.mesh = mesh;
  const bool flipped = before.faces_inward;  // orient_outward's own test, on the report already made
  if (flipped) flip_faces(result.mesh);
  if (!before.closed || !before.oriented)
    result.warnings.push_back(std::string("the mesh has no inside to face (it is ") +
                              (!before.manifold ? "not manifold"
                               : !before.closed ? "open: " + std::to_string(before.boundary_edges) + " boundary edges"
                                                : "inconsistently oriented") +
                              "): it is unchanged; Repair orients and closes what it can");
  result.metrics = Metrics{{"faces_flipped", flipped ? double(mesh.num_faces()) : 0.0},
                           {"volume_before", before.volume.value_or(0)},
                           {"volume_after", before.volume ? std::abs(*before.volume) : 0}};
  ctx.progress(1.0, "done");
  return result;
}

// A lambda, not the function's name: core/orient.h's orient_outward(Mesh&)
// shares it, and a name with two overloads cannot be passed on as one.
CGVIEW_REGISTER_FUNCTION(orient_outward, orient_outward,
                         {.title = "Orient outward",
                          .description = "Turns a closed mesh whose faces all face inward (a negative volume) "
                                         "outward, face indices kept; any other mesh comes back unchanged.",
                          .area = "filters"})

}  // namespace cgview
