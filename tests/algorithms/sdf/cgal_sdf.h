// CGAL's sdf_values on a mesh, the reference the SDF tests compare with.
#pragma once

#include <CGAL/mesh_segmentation.h>

#include <cstddef>
#include <numbers>
#include <vector>

#include "core/mesh.h"
#include "core/surface_mesh.h"

namespace cgview::test {

// CGAL's SDF, a value per face in the mesh's order: raw (-1 where it found
// none), or with its post-processing (missing values filled, its bilateral
// filter, normalized to [0, 1]).
inline std::vector<double> cgal_sdf_values(const Mesh& mesh, double cone_degrees, int rays, bool postprocess) {
  SurfaceMesh sm = manifold_surface_mesh(mesh, "the CGAL reference");
  auto map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
  CGAL::sdf_values(sm, map, cone_degrees * std::numbers::pi / 180.0, std::size_t(rays), postprocess);
  std::vector<double> out;
  for (SurfaceMesh::Face_index f : sm.faces()) out.push_back(map[f]);
  return out;
}

}  // namespace cgview::test
