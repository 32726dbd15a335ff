// Eigen views of a Mesh, for algorithms that need linear algebra (libigl's
// V and F).  Header-only; include it only where Eigen is used.
#pragma once

#include <Eigen/Core>

#include "core/mesh.h"

namespace cgview {

// V: one row per vertex (x, y, z).
inline Eigen::MatrixXd vertices_matrix(const Mesh& mesh) {
  Eigen::MatrixXd V(Eigen::Index(mesh.num_vertices()), 3);
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v)
    V.row(Eigen::Index(v)) << mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z;
  return V;
}
// F: one row per face (three vertex indices).
inline Eigen::MatrixXi faces_matrix(const Mesh& mesh) {
  Eigen::MatrixXi F(Eigen::Index(mesh.num_faces()), 3);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    F.row(Eigen::Index(f)) << int(mesh.faces[f][0]), int(mesh.faces[f][1]), int(mesh.faces[f][2]);
  return F;
}

}  // namespace cgview
