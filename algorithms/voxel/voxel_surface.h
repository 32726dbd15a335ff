// voxel_surface: the boundary of a mesh's voxels as a mesh (voxelize, then
// boundary_mesh with coplanar faces merged), so that the viewer shows the
// voxel surface as it shows any mesh artifact.
//
//   Mesh m = read_mesh("elephant.off");
//   VoxelSurfaceResult r = voxel_surface(m, {.resolution = 32});
//   write_mesh(r.mesh, "elephant-voxels.ply");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"
#include "voxel/voxelize.h"

namespace cgview {

struct VoxelSurfaceParams {
  int resolution = 64;
  VoxelizeMode mode = VoxelizeMode::solid;
  double max_memory_mb = 2048;
  template <class V>
  void describe(V& v) {
    describe_resolution(v, resolution);
    v.choice(
        "mode", mode,
        {.label = "Mode",
         .help = "solid: the outer surface of the solid voxels; surface: both sides of the shell of surface voxels",
         .choices = {"surface", "solid"}});
    describe_memory_limit(v, max_memory_mb);
  }
};

struct VoxelSurfaceResult {
  Mesh mesh;        // outward, coplanar voxel faces merged into rectangles
  Metrics metrics;  // voxels, voxel_size, triangles, volume
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput as voxelize does (a mesh without faces, a grid over
// max_memory_mb).
VoxelSurfaceResult voxel_surface(const Mesh& mesh, const VoxelSurfaceParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
