#include "core/vector_field.h"

#include <cmath>

#include "core/errors.h"
#include "core/mesh.h"

namespace cgview {

float VectorField::max_length() const {
  float most = 0;
  for (const Vec3f& v : values)
    if (const float n = norm(v); std::isfinite(n)) most = std::max(most, n);
  return most;
}

void VectorField::check_matches(const Mesh& mesh) const {
  const std::size_t want = location == Location::vertex ? mesh.num_vertices() : mesh.num_faces();
  if (values.size() != want)
    throw InvalidInput("vector field '" + name + "' has " + std::to_string(values.size()) +
                       " vectors but the mesh has " + std::to_string(want) +
                       (location == Location::vertex ? " vertices" : " faces"));
}

std::vector<Vec3> vector_origins(const Mesh& mesh, Location location) {
  if (location == Location::vertex) return mesh.positions;
  std::vector<Vec3> out;
  out.reserve(mesh.num_faces());
  for (const Tri& f : mesh.faces)
    out.push_back((mesh.positions[f[0]] + mesh.positions[f[1]] + mesh.positions[f[2]]) / 3.0);
  return out;
}

const char* to_string(VectorHint h) { return h == VectorHint::direction ? "direction" : "arrow"; }

}  // namespace cgview
