// Stage (d) of skeleton_projection: the skeleton of the vote grid.
//
// The voxels with at least `threshold` x the most votes, reached through
// those with a fifth of that (every voted voxel where that would part
// them); an intensity-driven shortest-path tree from the most voted voxel
// (a step costs its length over the voxel's normalized votes squared, so
// paths run along the ridge of votes, cf. Yim et al. 2000); branches taken
// as in TEASAR (Sato et al. 2000): the farthest voxel not yet covered gives
// a path back to the tree, kept if long enough and voted enough, and the
// voxels within 1.5 x the local radius around it are covered (thin.cpp);
// then loops (thin_tunnels.cpp, thin_gaps.cpp).
#pragma once

#include <functional>
#include <vector>

#include "core/skeleton.h"
#include "core/voxel_grid.h"
#include "skeleton/skeleton_projection.h"

namespace cgview::skeleton {

// The skeleton of the vote grid, nodes at voxel centres; `radius` (from
// vote) sets how far a branch covers the voxels around it (1.5 x the radius
// + 2 voxels, as TEASAR), how far apart along the skeleton the nodes where
// two meeting paths join must be (tunnels), and how far an end looks to
// close a loop (other meshes).
// With `inside` (the solid) and `max_loops` >= 0 (its genus), loops are
// tunnels: where the shortest-path trees meet themselves (neighbouring
// voxels whose paths join the skeleton further apart along it than their
// covering radii), the meetings that touch one another form a cut through
// a tunnel; each cut closes one loop, through its best voted meeting whose
// loop goes around a hole (the triangles from its centre to its edges cross
// the outside; a cut whose 8 best voted meetings go around none closes
// none), the best voted cuts first, at most max_loops.  Otherwise an
// end next to a far part of the skeleton through voted voxels closes one.
// Progress ("thinning", then "closing loops") goes to ctx over
// [progress_from, progress_to] as the shortest paths settle voxels and the
// loops are tried; ctx's cancellation throws Cancelled.
Skeleton thin(const VoxelGrid& votes, const std::vector<float>& radius, const SkeletonProjectionParams& p,
              int max_loops = -1, const std::function<bool(const Vec3&)>& inside = {}, const Context* ctx = nullptr,
              double progress_from = 0, double progress_to = 1);

}  // namespace cgview::skeleton
