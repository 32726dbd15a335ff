// Skeleton: a curve skeleton as a graph of nodes (positions, optional radii)
// and edges, with an optional map from mesh vertices to the node they
// collapse to (as CGAL's Mean_curvature_flow_skeletonization gives).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"
#include "core/vec.h"

namespace cgview {

struct Skeleton {
  std::vector<Vec3> nodes;
  std::vector<std::array<Index, 2>> edges;
  std::vector<float> radii;           // empty, or one per node
  std::vector<Index> vertex_to_node;  // empty, or one per mesh vertex

  std::size_t num_nodes() const { return nodes.size(); }
  std::size_t num_edges() const { return edges.size(); }
  // Throws InvalidInput for an edge index out of range, a loop edge, a
  // non-finite position, or radii of the wrong length.
  void validate() const;
};

// Neighbours of each node.
Adjacency skeleton_adjacency(const Skeleton& s);
// Number of edges at each node: 1 at an end, 2 along a branch, 3+ at a junction.
std::vector<std::uint32_t> node_degrees(const Skeleton& s);
// Sum of edge lengths.
double total_length(const Skeleton& s);
// Connected component of each node; returns the count.
std::uint32_t skeleton_components(const Skeleton& s, std::vector<std::uint32_t>& component);
// The branches: maximal paths whose inner nodes have degree 2, each as the
// node sequence from one end or junction to another; a cycle with no
// junction comes back as one closed path (first node repeated at the end).
std::vector<std::vector<Index>> skeleton_branches(const Skeleton& s);
// One pass of spur pruning: every terminal branch (from an end to a
// junction) for which drop(branch, length, tip) holds loses its edges; its
// nodes below degree 3 are left unused (not renumbered).  tip is the
// branch's end of degree 1.  Returns whether any branch went.
bool prune_spurs(Skeleton& s,
                 const std::function<bool(const std::vector<Index>& branch, double length, Index tip)>& drop);
BBox bounding_box(const Skeleton& s);

}  // namespace cgview
