// Stage (c) of skeleton_projection: each medial pixel of radius w casts its
// ray; the voxels from where it enters the shape to min(where it leaves,
// entry + 2 w) get a vote, and as the antipode's ray those from where it
// leaves back to max(entry, exit - 2 w) (inside the shape by the depth
// buffers, and no deeper than the disc the pixel is the centre of).
#pragma once

#include <vector>

#include "core/mesh.h"
#include "core/voxel_grid.h"
#include "skeleton/skeleton_projection.h"

namespace cgview {
class Context;
namespace render {
struct ViewCapture;
}  // namespace render

namespace skeleton {

// The vote grid's voxel: `grid` of them along the box's longest side.
double vote_voxel_size(const BBox& box, int grid);

// Votes (a float grid over the mesh's bounding box, `grid` voxels along
// its longest side, one voxel of margin) from views captured with their back
// depth (render::CaptureOptions; InvalidInput without), and for each voxel
// the mean radius (world units) of the medial discs that voted for it.
// Progress ("medial axes and votes") goes over [progress_from, progress_to]
// as the views are done, reported from the calling thread.
struct Votes {
  VoxelGrid grid;
  std::vector<float> radius;
};
Votes vote(const std::vector<render::ViewCapture>& views, const BBox& box, const SkeletonProjectionParams& p,
           const Context* ctx = nullptr, double progress_from = 0, double progress_to = 1);

}  // namespace skeleton
}  // namespace cgview
