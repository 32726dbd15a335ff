// fill_holes: closes holes (border cycles) with CGAL's hole filling (Liepa
// 2003): a minimal-weight triangulation, optionally refined to match the
// surrounding density and faired to blend with it.
//
//   Mesh m = read_mesh("elephant-with-holes.off");
//   FillHolesResult r = fill_holes(m, {.mode = FillHolesMode::triangulate});
//   write_mesh(r.mesh, "closed.off");  // r.metrics.at("holes_filled")
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

enum class FillHolesMode { triangulate, refine, refine_and_fair };

struct FillHolesParams {
  int max_hole_edges = 1000;
  FillHolesMode mode = FillHolesMode::refine_and_fair;
  bool repair = true;  // describe_repair (filters/repair_param.h)
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
    describe_repair(v, repair);
  }
};

struct FillHolesResult {
  Mesh mesh;
  Metrics metrics;  // holes_found, holes_filled
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces, or one that is not manifold
// with `repair` off.  Holes left open (too large, not triangulable) and
// fairings that failed are warnings.
FillHolesResult fill_holes(const Mesh& mesh, const FillHolesParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
