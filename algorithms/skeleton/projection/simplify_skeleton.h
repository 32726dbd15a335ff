// Stage (e) of skeleton_projection: internal arcs shorter than a length
// collapsed (branch nodes that are too close merged), then endpoint-
// preserving Laplacian smoothing of the nodes inside branches, which frees
// them from voxel centres.
#pragma once

#include <functional>

#include "core/skeleton.h"

namespace cgview::skeleton {

// Collapses internal arcs shorter than `merge_length` and smooths; a
// smoothing step that would take a node where `allowed` says no (outside the
// mesh) leaves it where it was.
void simplify(Skeleton& s, double merge_length, int smoothing_iterations,
              const std::function<bool(const Vec3&)>& allowed = {});

}  // namespace cgview::skeleton
