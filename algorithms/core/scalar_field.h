// ScalarField: one named float per vertex or per face, with its range and a
// hint for how to colour it (Polyscope's addVertexScalarQuantity).
#pragma once

#include <string>
#include <vector>

namespace cgview {

struct Mesh;

enum class Location { vertex, face };
// standard: a sequential map; symmetric: diverging around zero; magnitude:
// non-negative sizes; categorical: integer labels (segment ids).
enum class ColorHint { standard, symmetric, magnitude, categorical };

struct ScalarField {
  std::string name;
  Location location = Location::vertex;
  ColorHint hint = ColorHint::standard;
  std::vector<float> values;  // one per vertex or per face

  // Smallest and largest finite value ({0, 0} when there is none).
  std::pair<float, float> range() const;
  // Values mapped to [0, 1] over range() (0.5 where the range is empty).
  std::vector<float> normalized() const;
  // Throws InvalidInput unless there is one value per vertex (face) of mesh.
  void check_matches(const Mesh& mesh) const;
};

// Averages a per-face field onto vertices, weighting each face by its area.
ScalarField face_to_vertex(const Mesh& mesh, const ScalarField& per_face);

const char* to_string(Location l);
const char* to_string(ColorHint h);

}  // namespace cgview
