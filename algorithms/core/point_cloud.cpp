#include "core/point_cloud.h"

#include <string>

#include "core/errors.h"

namespace cgview {

void PointCloud::validate() const {
  for (std::size_t i = 0; i < positions.size(); ++i)
    if (!is_finite(positions[i])) throw InvalidInput("point " + std::to_string(i) + " has a non-finite coordinate");
  auto per_point = [&](std::size_t n, const char* what) {
    if (n != 0 && n != positions.size())
      throw InvalidInput("there are " + std::to_string(n) + " " + what + " for " + std::to_string(positions.size()) +
                         " points");
  };
  per_point(normals.size(), "normals");
  per_point(colors.size(), "colours");
}

PointCloud points_of(const Mesh& mesh) {
  PointCloud cloud;
  cloud.positions = mesh.positions;
  if (mesh.normal_faces.empty() && mesh.normals.size() == mesh.positions.size()) cloud.normals = mesh.normals;
  if (mesh.colors.size() == mesh.positions.size()) cloud.colors = mesh.colors;
  return cloud;
}

Mesh as_mesh(const PointCloud& cloud) {
  Mesh mesh;
  mesh.positions = cloud.positions;
  mesh.normals = cloud.normals;
  mesh.colors = cloud.colors;
  return mesh;
}

}  // namespace cgview
