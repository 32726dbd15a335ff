// Points in the order of a Morton curve (Z-order) through their bounding
// box: points near in the order lie near in space, so that work done in that
// order (a face's window, a face's rays) finds what it reads in the caches,
// whatever order a mesh's file lists its faces in.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/vec.h"

namespace cgview::sdf {

// The indices of `centre`, sorted by the Morton code of each point (10 bits
// an axis of the points' bounding box: a cell holds a face or two of a
// 1.42M-face mesh's centroids), points of one code in their given order.
std::vector<std::uint32_t> curve_order(std::span<const Vec3> centre);

}  // namespace cgview::sdf
