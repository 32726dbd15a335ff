// Stage (b) of skeleton_projection: the medial axis of a silhouette, from
// its (3,4) chamfer distance transform (Borgefors 1986; Sanniti di Baja
// 1994's skeletons): the centres of maximal discs, pixels p such that no
// neighbour q has dt(q) >= dt(p) + w(p, q) (w = 3 edge-, 4 corner-wise).
#pragma once

#include <cstdint>
#include <vector>

namespace cgview::skeleton {

// The (3,4) chamfer distance of each inside pixel to the outside (3 per
// pixel step, 4 per diagonal step; 0 outside; the image border is outside).
std::vector<std::uint16_t> chamfer_34(const std::vector<std::uint8_t>& mask, int width, int height);
// The centres of maximal discs with dt >= 3 * min_radius: 1 on the axis.
std::vector<std::uint8_t> medial_axis(const std::vector<std::uint16_t>& dt, int width, int height, int min_radius);

}  // namespace cgview::skeleton
