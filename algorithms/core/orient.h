// Turning a mesh whose faces all point into its solid (a closed mesh of
// negative volume) outward, as CGAL's orient_to_bound_a_volume would, but in
// place: each face keeps its index, so a per-face result computed on the
// turned mesh belongs to the original face for face.
#pragma once

#include "core/mesh.h"

namespace cgview {

// Reverses every face (its vertex, normal and UV triangles) and negates the
// normals.
void flip_faces(Mesh& mesh);

// Flips the faces of a closed, oriented mesh whose volume is negative; true
// when it did.  A mesh with no inside (open, non-manifold, inconsistently
// oriented) is left as it is: false.  Shells inside others keep facing
// into their hollow, since the volume counted is the whole mesh's.
bool orient_outward_in_place(Mesh& mesh);

}  // namespace cgview
