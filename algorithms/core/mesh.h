// Mesh: an indexed triangle mesh with optional normals, UVs and colours.
//
// The storage is the one that files, GPUs and Draco use (libigl's V/F with
// TC/FTC and N/FN): positions and triangles as arrays.  It can hold any input
// a file gives, non-manifold or badly oriented ones included, so that a report
// can describe it faithfully; algorithms that need halfedges convert it with
// to_surface_mesh() (core/surface_mesh.h), and Eigen users with core/eigen.h.
// See docs/DESIGN.md for why this and not a Surface_mesh as the stored type.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"

namespace cgview {

using Index = std::uint32_t;
using Tri = std::array<Index, 3>;

// Per-vertex attributes are stored with one value per position.  Normals and
// UVs may instead carry their own indices, one triangle of them per face (an
// OBJ's `f v/vt/vn`); then normal_faces / uv_faces has one Tri per face.
struct Mesh {
  std::vector<Vec3> positions;  // one per vertex
  std::vector<Tri> faces;       // one per face, counter-clockwise seen from outside

  std::vector<Vec3f> normals;     // empty, one per vertex, or indexed by normal_faces
  std::vector<Tri> normal_faces;  // empty, or one per face
  std::vector<Vec2f> uvs;         // empty, one per vertex, or indexed by uv_faces
  std::vector<Tri> uv_faces;      // empty, or one per face
  std::vector<Color> colors;      // empty, or one per vertex

  std::size_t num_vertices() const { return positions.size(); }
  std::size_t num_faces() const { return faces.size(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_uvs() const { return !uvs.empty(); }
  bool has_colors() const { return !colors.empty(); }
  // True when normals/UVs are per vertex (no separate index triangles).
  bool attributes_per_vertex() const { return normal_faces.empty() && uv_faces.empty(); }

  // Throws InvalidInput naming the first inconsistency: an index out of range,
  // an attribute array of the wrong length, or a non-finite coordinate.
  void validate() const;
};

BBox bounding_box(const Mesh& mesh);

// cross(b - a, c - a) of face f = (a, b, c): its direction is the face
// normal, its length twice the face's area.
inline Vec3 face_cross(const Mesh& mesh, std::size_t f) {
  const Tri& t = mesh.faces[f];
  const auto& P = mesh.positions;
  return cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
}

// The centroid of face f: the mean of its three corners.
inline Vec3 face_centroid(const Mesh& mesh, std::size_t f) {
  const Tri& t = mesh.faces[f];
  const auto& P = mesh.positions;
  return (P[t[0]] + P[t[1]] + P[t[2]]) / 3.0;
}

// Unit normal of each face (zero for a degenerate face).  One per face.
std::vector<Vec3> face_normals(const Mesh& mesh);
// The area of each face.  One per face.
std::vector<double> face_areas(const Mesh& mesh);
// The volume a closed, consistently oriented mesh encloses: positive when its
// faces are counter-clockwise seen from outside, negative when they face in
// (the divergence theorem; meaningless for an open mesh).
double signed_volume(const Mesh& mesh);

enum class NormalWeighting { uniform, area, angle };
// Unit vertex normals, the face normals averaged with the given weights
// (angle-weighted by default: Thürmer and Wüthrich 1998).  One per vertex.
std::vector<Vec3> vertex_normals(const Mesh& mesh, NormalWeighting w = NormalWeighting::angle);

// A compressed adjacency list (CSR): the neighbours of item i are
// items[offsets[i] .. offsets[i+1]).
struct Adjacency {
  std::vector<std::uint32_t> offsets;
  std::vector<std::uint32_t> items;
  std::size_t size() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::size_t degree(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  const std::uint32_t* begin(std::size_t i) const { return items.data() + offsets[i]; }
  const std::uint32_t* end(std::size_t i) const { return items.data() + offsets[i + 1]; }
};

// Faces incident to each vertex (in face order).
Adjacency vertex_faces(const Mesh& mesh);
// Neighbouring vertices of each vertex (sorted, no repeats).
Adjacency vertex_neighbors(const Mesh& mesh);

// The undirected edges of a mesh and which faces use them.
struct EdgeTopology {
  std::vector<std::array<Index, 2>> edges;       // (a, b) with a < b; one per edge
  std::vector<std::array<Index, 3>> face_edges;  // edge ids of each face: (v0v1, v1v2, v2v0)
  Adjacency edge_faces;                          // faces using each edge: 1 on a border, 2 inside, more if non-manifold
};
// Edges of non-degenerate face sides (a side whose two ends coincide is skipped
// and gets the id UINT32_MAX in face_edges).
EdgeTopology edge_topology(const Mesh& mesh);

// The dual graph: for each face, the faces sharing an edge with it.
Adjacency face_neighbors(const Mesh& mesh, const EdgeTopology& topology);

// Connected component id of each vertex (vertices joined by face edges);
// isolated vertices form components of their own.  Returns the count.
std::uint32_t vertex_components(const Mesh& mesh, std::vector<std::uint32_t>& component);

// A copy whose normals, UVs and colours are per vertex: vertices are split
// where a face corner's attribute index differs (what GPUs and glTF need).
Mesh with_per_vertex_attributes(const Mesh& mesh);

// Midpoint subdivision: each triangle into four.  Attributes are dropped.
Mesh subdivide_midpoint(const Mesh& mesh);

}  // namespace cgview
