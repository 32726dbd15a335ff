// chaos_map: a chaotic map (Ikeda, Arnold's cat, logistic, Henon, or a 3D
// composition) applied `steps` times to the normalized vertex positions,
// as in the CGView paper's Figure 11 (the Ikeda map on the bunny).
// Teaching code: see docs/CHAOS.md.
//
//   Mesh m = read_mesh("bunny.off");
//   ChaosMapResult r = chaos_map(m, {.map = {.kind = chaos::MapKind::ikeda, .u = 0.9}, .steps = 5});
//   write_mesh(r.mesh, "ikeda5.ply");
#pragma once

#include <string>
#include <vector>

#include "chaos/chaos_params.h"
#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ChaosMapParams {
  chaos::MapParams map{};
  int steps = 1;
  template <class V>
  void describe(V& v) {
    chaos::describe_map(v, map);
    v.integer("steps", steps, {.label = "Steps", .min = 0, .max = 1000, .help = "how many times the map is applied"});
  }
};

struct ChaosMapResult {
  Mesh mesh;  // the input with moved positions and no normals
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a mesh without vertices.  Vertices that leave
// every bound are frozen, and a warning counts them.
ChaosMapResult chaos_map(const Mesh& mesh, const ChaosMapParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
