// subdivide: CGAL's subdivision surfaces (Subdivision_method_3): Loop,
// Catmull-Clark (its quads triangulated afterwards) and Kobbelt's sqrt(3).
//
//   Mesh m = read_mesh("bunny.off");
//   SubdivideResult r = subdivide(m, {.method = SubdivideMethod::sqrt3, .iterations = 2});
//   write_mesh(r.mesh, "bunny_sqrt3.off");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

enum class SubdivideMethod { loop, catmull_clark, sqrt3 };

struct SubdivideParams {
  SubdivideMethod method = SubdivideMethod::loop;
  int iterations = 1;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.choice("method", method,
             {.label = "Method",
              .help = "loop: smooth, each triangle into 4; catmull_clark: quads, each triangle into 3 "
                      "then each quad into 4 per step, split into 2 triangles each at the end; sqrt3: Kobbelt's "
                      "scheme, each triangle into 3",
              .choices = {"loop", "catmull_clark", "sqrt3"}});
    v.integer("iterations", iterations, {.label = "Iterations", .min = 1, .max = 5, .help = "subdivision steps"});
    describe_repair(v, repair);
  }
};

struct SubdivideResult {
  Mesh mesh;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Attributes (normals, UVs, colours) are dropped.  Throws InvalidInput for a
// mesh without faces, one that is not manifold with `repair` off, or one whose
// result would have more than 20 million faces.
SubdivideResult subdivide(const Mesh& mesh, const SubdivideParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
