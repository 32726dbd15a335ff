// repair: cleans a triangle soup and rebuilds a manifold mesh from it, with
// CGAL's polygon soup tools (filters/repair_mesh.h), with a report of what
// changed.  It works on the soup, so it accepts what no halfedge structure can
// hold (three faces on an edge, a bowtie vertex); a closed result facing
// inward is turned outward (core/orient.h) unless asked not to.
//
//   Mesh soup = read_mesh("scan.stl");
//   RepairResult r = repair(soup, {.stitch = true});
//   write_mesh(r.mesh, "repaired.off");  // r.metrics.at("faces_removed"), ...
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct RepairParams {
  bool stitch = true;
  bool outward = true;
  template <class V>
  void describe(V& v) {
    v.boolean("stitch", stitch, {.label = "Stitch borders", .help = "glue border edges whose end points coincide"});
    v.boolean("outward", outward,
              {.label = "Orient outward", .help = "turn a closed mesh whose faces all face inward outward"});
  }
};

struct RepairResult {
  Mesh mesh;
  // What changed (faces_removed, vertices_merged, isolated_vertices_removed,
  // vertices_duplicated, borders_stitched, faces_turned_outward) and the
  // mesh before and after ({vertices,faces}_{before,after},
  // {manifold,closed}_{before,after} as 0 or 1).
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a mesh without faces, or whose faces are all
// degenerate.
RepairResult repair(const Mesh& mesh, const RepairParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
