// normals: angle-weighted vertex normals from CGAL's Polygon Mesh Processing
// (compute_vertex_normals; Thürmer and Wüthrich 1998).
//
//   Mesh m = read_mesh("bunny.off");
//   NormalsResult r = normals(m);
//   write_mesh(r.mesh, "bunny_normals.ply");  // one unit normal per vertex
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct NormalsParams {
  template <class V>
  void describe(V&) {}
};

struct NormalsResult {
  Mesh mesh;  // the input with one normal per vertex (indexed normals dropped)
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a mesh without faces.  Faces no halfedge structure
// can hold (non-manifold, degenerate) are left out of the normals, with a
// warning.
NormalsResult normals(const Mesh& mesh, const NormalsParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
