// voxel_distance: a scalar grid (a float per voxel), the Euclidean distance
// from each solid voxel to the outside (voxelize, then distance_transform):
// the medial "depth" of the shape, which the viewer shows in slices with a
// threshold slider.
//
//   Mesh m = read_mesh("elephant.off");
//   VoxelDistanceResult r = voxel_distance(m, {.resolution = 64});
//   write_voxel_grid(r.distance, "depth.nrrd");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/voxel_grid.h"
#include "registry/registry.h"
#include "voxel/voxelize.h"

namespace cgview {

struct VoxelDistanceParams {
  int resolution = 64;
  double max_memory_mb = 2048;
  template <class V>
  void describe(V& v) {
    describe_resolution(v, resolution, 4096);
    describe_memory_limit(v, max_memory_mb, "1 byte per voxel, and 12 more for the distances");
  }
};

struct VoxelDistanceResult {
  VoxelGrid distance;  // float32: 0 outside the solid
  Metrics metrics;     // max_distance, min_distance, voxel_size, voxels
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("distance", distance);
    v("metrics", metrics);
  }
};

// Throws InvalidInput as voxelize does; its memory limit counts the
// distances (13 bytes per voxel in all), and the message says so.
VoxelDistanceResult voxel_distance(const Mesh& mesh, const VoxelDistanceParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
