// Meshes and comparisons the chaos tests share (header-only).
#pragma once

#include <cstring>
#include <vector>

#include "core/mesh.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview::test {

// Sample meshes of different kinds: large, open, a box, with colours.
inline std::vector<Mesh> chaos_sample_meshes() {
  std::vector<Mesh> out;
  for (const char* n : {"elephant.off", "bunny00.off", "cube.off", "colored_tetra.ply"})
    out.push_back(read_mesh(sample(n)));
  return out;
}

// The same positions, bit for bit (-0.0 and denormals included).
inline bool bit_equal(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

}  // namespace cgview::test
