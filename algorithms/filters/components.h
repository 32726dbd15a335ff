// components: connected components of the faces (CGAL Polygon Mesh
// Processing's connected_components): count them, keep the largest, or drop
// the small ones.
//
//   Mesh m = read_mesh("scan.off");
//   ComponentsResult r = components(m, {.mode = ComponentsMode::drop_smaller_than, .min_faces = 50});
//   double n = r.metrics.at("components"), kept = r.metrics.at("kept");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

enum class ComponentsMode { keep_largest, drop_smaller_than, count };

struct ComponentsParams {
  ComponentsMode mode = ComponentsMode::keep_largest;
  int min_faces = 100;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.choice("mode", mode,
             {.label = "Mode",
              .help = "keep_largest: the component with the most faces; drop_smaller_than: remove components with "
                      "fewer than min_faces faces; count: only count them (the mesh comes back unchanged)",
              .choices = {"keep_largest", "drop_smaller_than", "count"}});
    v.integer("min_faces", min_faces,
              {.label = "Minimum faces",
               .min = 1,
               .max = 1e9,
               .help = "for drop_smaller_than: the smallest size kept",
               .when = {"mode", {"drop_smaller_than"}}});
    describe_repair(v, repair);
  }
};

struct ComponentsResult {
  Mesh mesh;        // the components kept (the input itself for count)
  Metrics metrics;  // "components": how many there were; "kept": how many remain
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces, or one that is not manifold
// with `repair` off.
ComponentsResult components(const Mesh& mesh, const ComponentsParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
