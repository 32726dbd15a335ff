// mesh_report: counts and topological facts of a mesh, as MeshLab's
// "Compute Topological Measures" and `cgview info` show them.
//
// Euler characteristic chi = V - E + F (V counts vertices used by faces).
// For a manifold, consistently oriented mesh with C components and B
// boundary loops, genus = (2C - chi - B) / 2 (summed over the components).
#pragma once

#include <cstdint>
#include <optional>

#include "core/mesh.h"

namespace cgview {

struct MeshReport {
  std::uint64_t vertices = 0, faces = 0, edges = 0;
  BBox bbox;
  std::uint64_t components = 0;                      // face-connected pieces (isolated vertices excluded)
  std::uint64_t isolated_vertices = 0;               // vertices no face uses
  std::uint64_t boundary_edges = 0;                  // edges with one face
  std::uint64_t boundary_loops = 0;                  // connected chains of boundary edges
  std::uint64_t non_manifold_edges = 0;              // edges with more than two faces
  std::uint64_t non_manifold_vertices = 0;           // vertices whose faces form more than one fan
  std::uint64_t inconsistent_edges = 0;              // interior edges whose two faces disagree on orientation
  std::uint64_t degenerate_faces = 0;                // a repeated vertex or zero area
  std::uint64_t duplicate_faces = 0;                 // faces on the same three vertices as an earlier face
  bool manifold = false;                             // no non-manifold edge or vertex
  bool closed = false;                               // manifold with no boundary edge
  bool oriented = false;                             // manifold and every interior edge is used once in each direction
  std::optional<std::int64_t> euler_characteristic;  // of the used vertices, edges, faces
  std::optional<std::int64_t> genus;                 // when manifold and oriented
  double area = 0;                                   // total surface area
  std::optional<double> volume;                      // enclosed volume, when closed and oriented
  // Closed and oriented with a negative volume: every face points into the
  // solid (a common export error).  What needs the inside (the SDF) would
  // cast its rays outward; orient_outward (core/orient.h) turns it.
  bool faces_inward = false;
  // Points and no faces: a point cloud (core/point_cloud.h).
  bool point_cloud() const { return faces == 0 && vertices > 0; }
};

// Computes the report in O(n log n).  Never throws for a validated mesh.
MeshReport mesh_report(const Mesh& mesh);

}  // namespace cgview
