// grid_surface: the boundary of a voxel grid as a mesh, coplanar voxel faces
// merged (boundary_mesh), after a threshold for scalar grids
// (voxel_distance's distances, a skeleton's vote grid).  Its input is a
// grid, not a mesh: a job names it {"job": ID, "artifact": "grid"},
// `cgview run grid_surface e.nrrd` reads it from a file.
//
//   VoxelGrid g = read_voxel_grid("depth.nrrd");
//   GridSurfaceResult r = grid_surface(g, {.threshold = 0.05});
//   write_mesh(r.mesh, "deep.ply");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/voxel_grid.h"
#include "registry/registry.h"

namespace cgview {

struct GridSurfaceParams {
  double threshold = 0;
  template <class V>
  void describe(V& v) {
    v.number("threshold", threshold,
             {.label = "Threshold",
              .min = -1e30,
              .max = 1e30,
              .help = "the voxels whose value is above it (occupancy grids: 0 keeps every occupied voxel)"});
  }
};

struct GridSurfaceResult {
  Mesh mesh;        // outward, coplanar voxel faces merged into rectangles
  Metrics metrics;  // voxels, voxel_size, volume
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// No voxel above the threshold gives an empty mesh and a warning.
GridSurfaceResult grid_surface(const VoxelGrid& grid, const GridSurfaceParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
