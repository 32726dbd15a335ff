// Operations on voxel grids: the distance transform, the boundary as a
// mesh, and the topology (components, cavities, tunnels) of the occupied
// voxels, the simple-point test, slices.  Neighbourhoods and components are
// members of VoxelGrid (core/voxel_grid.h).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/voxel_grid.h"

namespace cgview {

// Whether occupied voxel v is simple for the (26, 6) connectivities: its
// removal changes no topology (no component, cavity or tunnel appears or
// vanishes).  The local characterization of Bertrand and Malandain ("A new
// characterization of three-dimensional simple points", Pattern Recognition
// Letters 1994): the occupied voxels of N26(v) \ {v} form exactly one
// 26-component, and the empty voxels of N18(v) \ {v} exactly one
// 6-component that holds a face neighbour of v.  Voxels outside the grid
// count as empty.  False for an empty voxel.
bool is_simple(const VoxelGrid& grid, VoxelIndex v);

struct DistanceTransformParams {
  // true: for each occupied voxel, the distance from its centre to the
  // nearest empty voxel's centre (0 on empty voxels);
  // false: for each voxel, the distance to the nearest occupied voxel's
  // centre (0 on occupied voxels).
  bool inside = true;
};

// The exact Euclidean distance transform (Felzenszwalb and Huttenlocher,
// "Distance transforms of sampled functions", Theory of Computing 2012:
// three separable passes of the lower envelope of parabolas, O(voxels)).
//   D(v) = voxel_size * min over feature voxels w of |v - w|.
// Only voxels inside the grid count as features; with none at all every
// value is +infinity.  Returns a float32 grid of the same geometry, one
// value per voxel.
VoxelGrid distance_transform(const VoxelGrid& grid, const DistanceTransformParams& params = {});

// The boundary of the occupied voxels as a triangle mesh: every voxel face
// between an occupied voxel and an empty one (or the outside of the grid),
// with coplanar faces merged greedily into rectangles (two triangles each),
// oriented outwards.  Rectangles may meet in T-junctions, so the mesh is
// closed geometrically but not combinatorially.  Positions in world units.
Mesh boundary_mesh(const VoxelGrid& grid);

// A 2D slice of a grid: the voxels whose `axis` index (0 x, 1 y, 2 z) is
// `index`, width x height values row by row, the first of the two other
// axes fastest (z slice: x fastest then y; x slice: y then z; y slice: x
// then z).  Throws InvalidInput for an axis other than 0..2 or an index
// outside the grid, naming the valid range.
struct VoxelSlice {
  int axis = 2, index = 0;
  int width = 0, height = 0;
  std::vector<float> values;  // width * height
};
VoxelSlice slice(const VoxelGrid& grid, int axis, int index);

// The voxels of a scalar grid above a threshold: a bit grid of the same
// geometry, 1 where value > threshold (strictly).  For the vote grids and
// distance fields that the viewer shows with a threshold slider.
VoxelGrid threshold(const VoxelGrid& grid, float threshold);

// The smallest and largest value of a grid (0, 0 for an empty one).
std::pair<float, float> value_range(const VoxelGrid& grid);

struct VoxelTopology {
  std::size_t components = 0;  // 26-connected components of occupied voxels (b0)
  std::size_t cavities = 0;    // 6-connected components of empty voxels enclosed by them (b2)
  std::size_t tunnels = 0;     // b1 = b0 + b2 - euler (handles, "genus" of a solid)
  long long euler = 0;         // V - E + F - C of the union of the closed occupied cubes
};
// The Betti numbers of the union of the closed occupied cubes (the (26, 6)
// pair of connectivities), the tunnels from the Euler characteristic.
VoxelTopology voxel_topology(const VoxelGrid& grid);

}  // namespace cgview
