// Helpers the voxel tests share (header-only): a mesh's volume, voxelize
// at a resolution, the message of an InvalidInput.
#pragma once

#include <functional>
#include <string>

#include "core/errors.h"
#include "core/mesh.h"
#include "voxel/voxelize.h"

namespace cgview::test {

// The signed volume a closed, outward mesh encloses.
inline double mesh_volume(const Mesh& m) {
  double v = 0;
  for (const Tri& t : m.faces) v += dot(m.positions[t[0]], cross(m.positions[t[1]], m.positions[t[2]])) / 6.0;
  return v;
}

inline VoxelizeResult vox(const Mesh& m, int res, VoxelizeMode mode, int padding = 1) {
  return voxelize(m, {.resolution = res, .mode = mode, .padding = padding});
}

// The message of the InvalidInput f throws, or "(no InvalidInput thrown)".
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no InvalidInput thrown)";
}

}  // namespace cgview::test
