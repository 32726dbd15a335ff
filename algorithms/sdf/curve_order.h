// Points in the order of a Morton curve (Z-order) through their bounding
// box: points near in the order lie near in space, so that work done in that
// order (a face's window, a face's rays) finds what it reads in the caches,
// whatever order a mesh's file lists its faces in.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh.h"
#include "core/vec.h"

namespace cgview::sdf {

// The indices of `centre`, sorted by the Morton code of each point (10 bits
// an axis of the points' bounding box: a cell holds a face or two of a
// 1.42M-face mesh's centroids), points of one code in their given order.
std::vector<std::uint32_t> curve_order(std::span<const Vec3> centre);

// The places i in `faces` (every face of `mesh` when it is empty), sorted
// as above by the centroids of their faces, made on every core.
std::vector<std::uint32_t> face_curve_order(const Mesh& mesh, std::span<const std::uint32_t> faces = {});

}  // namespace cgview::sdf
