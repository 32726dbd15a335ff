// orient_outward: turns a closed mesh whose faces all face inward (a
// negative volume, a common export error) outward (core/orient.h).  A mesh
// that already faces outward comes back as it was; one with no inside (open,
// non-manifold) too, with a warning that says why.
//
//   const Mesh m = read_mesh("inside_out.stl");
//   OrientOutwardResult r = orient_outward(m);
//   write_mesh(r.mesh, "outward.stl");  // r.metrics.at("faces_flipped")
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct OrientOutwardParams {
  template <class V>
  void describe(V&) {}
};

struct OrientOutwardResult {
  Mesh mesh;
  Metrics metrics;  // faces_flipped, volume_before, volume_after
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces.
OrientOutwardResult orient_outward(const Mesh& mesh, const OrientOutwardParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
