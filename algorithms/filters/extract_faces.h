// extract_faces: the selected faces of a mesh as a mesh of their own (or,
// with invert, the mesh without them): MeshLab's "Move selected faces to
// another layer" / "Delete selected faces".  It is the example of an
// algorithm that takes the viewer's selection as an input (a faces
// parameter, see registry.h).
//
//   Mesh m = read_mesh("grid.off");
//   ExtractFacesResult r = extract_faces(m, {.faces = {0, 1, 9}});
//   write_mesh(r.mesh, "three_faces.off");  // r.metrics.at("area"): their area
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ExtractFacesParams {
  Ids faces;
  bool invert = false;
  template <class V>
  void describe(V& v) {
    v.faces("faces", faces, {.label = "Faces", .help = "the ids of the faces to extract (the viewer's selection)"});
    v.boolean("invert", invert, {.label = "Delete instead", .help = "keep the other faces: delete the selected ones"});
  }
};

struct ExtractFacesResult {
  Mesh mesh;        // the faces kept, in their order, with only the vertices they use
  Metrics metrics;  // "faces", "vertices" and "area" of that mesh
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput when no face is selected or an id is out of range.
ExtractFacesResult extract_faces(const Mesh& mesh, const ExtractFacesParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
