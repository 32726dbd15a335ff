// VectorField: one named 3D vector per vertex or per face (Polyscope's
// addVertexVectorQuantity): directions, flows, gradients.  Drawn as arrows
// from the vertex, or from the face's centroid.
#pragma once

#include <string>
#include <vector>

#include "core/scalar_field.h"
#include "core/vec.h"

namespace cgview {

struct Mesh;

// direction: unit vectors whose sign means nothing (principal directions):
// drawn as lines through the point, of one length.  arrow: vectors whose
// length and sign mean something: drawn as arrows scaled by their length.
enum class VectorHint { arrow, direction };

struct VectorField {
  std::string name;
  Location location = Location::vertex;
  VectorHint hint = VectorHint::arrow;
  std::vector<Vec3f> values;  // one per vertex or per face

  // The longest finite vector's length (0 when there is none).
  float max_length() const;
  // Throws InvalidInput unless there is one vector per vertex (face) of mesh.
  void check_matches(const Mesh& mesh) const;
};

// Where each vector of the field sits on `mesh`: its vertex, or its face's centroid.
std::vector<Vec3> vector_origins(const Mesh& mesh, Location location);

const char* to_string(VectorHint h);

}  // namespace cgview
