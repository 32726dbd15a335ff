// cluster_decimate: a fast, coarse simplification by vertex clustering on a
// uniform grid (Rossignac and Borrel 1993, "Multi-resolution 3D
// approximations for rendering complex scenes"), the method viewers use for
// level-of-detail previews.  It is linear in the mesh size (a 2M-triangle
// mesh takes a second or so), unlike an edge-collapse simplification.
//
// Every vertex falls in a cubic cell of side h; the vertices of a cell merge
// into one, at their mean (so it lies inside the cell: the bounding box
// shrinks by less than h on each side).  A triangle survives when its three
// corners land in three different cells; duplicates are kept once.  h is
// chosen so that at most `target_faces` triangles remain (found by a few
// passes, each growing h).  The result may be non-manifold where thin parts
// collapse; a preview does not mind.
#pragma once

#include <cstddef>

#include "core/mesh.h"

namespace cgview {

struct ClusterDecimateParams {
  std::size_t target_faces = 100000;  // the most triangles kept (>= 1)
};

struct ClusterDecimateResult {
  Mesh mesh;               // positions, faces, and per-vertex colours (averaged) when the input has them
  double cell_size = 0.0;  // h; 0 when the input already had few enough faces (then mesh is a copy)
};

// Throws InvalidInput when target_faces is 0 or the mesh is invalid.
// Normals and UVs are dropped (the viewer computes normals).
ClusterDecimateResult cluster_decimate(const Mesh& mesh, const ClusterDecimateParams& params = {});

}  // namespace cgview
