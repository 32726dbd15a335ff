#include "core/scalar_field.h"

#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/mesh.h"

namespace cgview {

std::pair<float, float> ScalarField::range() const {
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (float v : values)
    if (std::isfinite(v)) {
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  if (lo > hi) return {0.f, 0.f};
  return {lo, hi};
}

std::vector<float> ScalarField::normalized() const {
  auto [lo, hi] = range();
  std::vector<float> out(values.size(), 0.5f);
  if (hi > lo)
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = (values[i] - lo) / (hi - lo);
  return out;
}

void ScalarField::check_matches(const Mesh& mesh) const {
  const std::size_t want = location == Location::vertex ? mesh.num_vertices() : mesh.num_faces();
  if (values.size() != want)
    throw InvalidInput("scalar field '" + name + "' has " + std::to_string(values.size()) +
                       " values but the mesh has " + std::to_string(want) + " " +
                       (want == 1                      ? to_string(location)
                        : location == Location::vertex ? "vertices"
                                                       : "faces"));
}

ScalarField face_to_vertex(const Mesh& mesh, const ScalarField& per_face) {
  if (per_face.location != Location::face) throw InvalidInput("face_to_vertex needs a per-face field");
  per_face.check_matches(mesh);
  const std::vector<double> area = face_areas(mesh);
  std::vector<double> sum(mesh.num_vertices(), 0.0), weight(mesh.num_vertices(), 0.0);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    for (Index v : mesh.faces[f]) {
      sum[v] += area[f] * per_face.values[f];
      weight[v] += area[f];
    }
  ScalarField out{per_face.name, Location::vertex, per_face.hint, {}};
  out.values.resize(mesh.num_vertices());
  for (std::size_t v = 0; v < sum.size(); ++v) out.values[v] = weight[v] > 0 ? float(sum[v] / weight[v]) : 0.f;
  return out;
}

const char* to_string(Location l) { return l == Location::vertex ? "vertex" : "face"; }
const char* to_string(ColorHint h) {
  switch (h) {
    case ColorHint::standard:
      return "standard";
    case ColorHint::symmetric:
      return "symmetric";
    case ColorHint::magnitude:
      return "magnitude";
    case ColorHint::categorical:
      return "categorical";
  }
  return "standard";
}

}  // namespace cgview
