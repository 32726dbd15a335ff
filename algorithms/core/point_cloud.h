// PointCloud: points with optional normals and colours, as scanners and
// photogrammetry write them (Open3D's PointCloud, Polyscope's point cloud).
//
// Files hold a cloud as a mesh with no faces (a PLY of vertices, an OBJ of
// `v` lines, an XYZ), so readers and writers go through Mesh: points_of()
// takes any mesh's vertices as a cloud, and as_mesh() gives the faceless
// mesh a writer takes.
#pragma once

#include <vector>

#include "core/mesh.h"
#include "core/vec.h"

namespace cgview {

struct PointCloud {
  std::vector<Vec3> positions;
  std::vector<Vec3f> normals;  // empty, or one per point
  std::vector<Color> colors;   // empty, or one per point

  std::size_t size() const { return positions.size(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_colors() const { return !colors.empty(); }
  // Throws InvalidInput naming the first inconsistency: a non-finite
  // coordinate, or normals or colours not one per point.
  void validate() const;
};

// A mesh's vertices as a cloud, with their normals and colours when they are
// one per vertex (normals indexed per face corner are dropped).
PointCloud points_of(const Mesh& mesh);
// The cloud as a mesh with no faces.
Mesh as_mesh(const PointCloud& cloud);

}  // namespace cgview
