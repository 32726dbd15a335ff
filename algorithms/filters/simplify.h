// simplify: edge-collapse decimation with Garland–Heckbert quadric error
// metrics (Garland and Heckbert 1997), CGAL's Surface_mesh_simplification.
//
//   Mesh m = read_mesh("elephant.off");
//   SimplifyResult r = simplify(m, {.target_faces = 1000});  // or {.ratio = 0.1}
//   write_mesh(r.mesh, "small.off");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct SimplifyParams {
  int target_faces = 0;
  double ratio = 0.5;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.integer(
        "target_faces", target_faces,
        {.label = "Target faces",
         .min = 0,
         .max = 1e9,
         .help = "stop at this many faces or fewer; 0 means use the ratio (when above 0, it wins over the ratio)"});
    v.number("ratio", ratio,
             {.label = "Ratio",
              .min = 0,
              .max = 1,
              .help = "fraction of the input's faces to keep, used when target_faces is 0"});
    describe_repair(v, repair);
  }
};

struct SimplifyResult {
  Mesh mesh;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a mesh without faces, or one that is not manifold
// with `repair` off.  Stopping above the target (no edge left that can
// collapse without breaking the mesh) is a warning.
SimplifyResult simplify(const Mesh& mesh, const SimplifyParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
