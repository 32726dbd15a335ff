// Meshes as students' scans have them: closed shapes that touch at a vertex
// or share an edge, one vertex index for both, so that no halfedge
// structure holds them (header-only).  The algorithms that need a manifold
// mesh repair a copy of such a mesh by default (filters/repair_param.h).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <map>

#include "core/mesh.h"
#include "test_support.h"

namespace cgview::test {

// The mesh with the vertices at one position made one (the first).
inline Mesh welded(const Mesh& m) {
  Mesh out;
  std::map<std::array<double, 3>, Index> at;
  std::vector<Index> id(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3& p = m.positions[i];
    const auto [it, fresh] = at.emplace(std::array<double, 3>{p.x, p.y, p.z}, Index(out.positions.size()));
    if (fresh) out.positions.push_back(p);
    id[i] = it->second;
  }
  for (const Tri& t : m.faces) out.faces.push_back({id[t[0]], id[t[1]], id[t[2]]});
  return out;
}

inline Mesh shifted(Mesh m, Vec3 by) {
  for (Vec3& p : m.positions) p += by;
  return m;
}

// Two unit spheres, one on top of the other, whose poles are one vertex:
// a non-manifold (bow-tie) vertex.  Each sphere is closed, genus 0.
inline Mesh two_spheres_touching(int rings = 16, int segments = 32) {
  const Mesh a = uv_sphere(1.0, rings, segments);
  return welded(merged(a, shifted(a, {0, 0, 2})));
}

// Two unit cubes side by side along a diagonal, sharing the edge x = y = 1:
// four faces on that edge.
inline Mesh two_boxes_sharing_an_edge() { return welded(merged(box({0, 0, 0}, {1, 1, 1}), box({1, 1, 0}, {2, 2, 1}))); }

// The stored input stays as it was.
inline void expect_same_mesh(const Mesh& a, const Mesh& b) {
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.faces, b.faces);
}

}  // namespace cgview::test
