// Shapes and measures the filters' tests share (header-only).
#pragma once

#include <cmath>
#include <random>

#include "core/mesh.h"
#include "core/mesh_report.h"
#include "test_support.h"

namespace cgview::test {

inline double mean_edge_length(const Mesh& m) {
  const EdgeTopology t = edge_topology(m);
  double sum = 0;
  for (const auto& e : t.edges) sum += norm(m.positions[e[0]] - m.positions[e[1]]);
  return sum / double(t.edges.size());
}

// The variance of the vertices' distances to the origin: 0 on a sphere.
inline double radius_variance(const Mesh& m) {
  double sum = 0, sum2 = 0;
  for (const Vec3& p : m.positions) {
    sum += norm(p);
    sum2 += norm(p) * norm(p);
  }
  const double n = double(m.num_vertices()), mean = sum / n;
  return sum2 / n - mean * mean;
}

// A unit sphere whose vertices are moved along their radius by up to 3%.
inline Mesh noisy_sphere() {
  Mesh m = uv_sphere(1.0, 24, 48);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.03, 0.03);
  for (Vec3& p : m.positions) p = p * (1.0 + noise(rng));
  return m;
}

// Three triangles on the edge (0, 1): no halfedge structure can hold them.
inline Mesh non_manifold() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

// A sphere with one more face on one of its edges: three faces on an edge,
// which the halfedge filters refuse unless asked to repair it first.
inline Mesh sphere_with_a_fin() {
  Mesh m = uv_sphere(1.0, 16, 32);
  const Tri f = m.faces[40];
  m.positions.push_back({3, 3, 3});
  m.faces.push_back({f[0], f[1], Index(m.positions.size() - 1)});
  return m;
}

// Every edge has exactly two faces.
inline bool closed(const Mesh& m) {
  const EdgeTopology t = edge_topology(m);
  for (std::size_t e = 0; e < t.edges.size(); ++e)
    if (t.edge_faces.degree(e) != 2) return false;
  return true;
}

}  // namespace cgview::test
