// CGAL's bilateral filter of per-face values (Surface_mesh_segmentation's
// Bilateral_filtering with its Neighbor_selector_by_edge): each face becomes
// the average of the faces within `window` edge-rings (window =
// floor(sqrt(faces / 2000)) + 1 by default), weighted by
//   exp(-ring^2 / (2 (window/2)^2)) exp(-dv^2 / (2 (1.5 s)^2)),
// s the RMS deviation of the window's values from the face's.
//
// The same sums as CGAL's, found faster: faces go in blocks of up to 64
// neighbours, and one breadth-first walk per block carries a bit per face of
// the block, so that a face near all of them is visited once per ring it
// lies on rather than once per face (windows of 27 rings on a 1.42M-face
// mesh hold about 1,100 faces each).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/mesh.h"

namespace cgview {
class Context;
}

namespace cgview::sdf {

// Smooths `values` (one per face of face_graph) in place; only the faces
// listed in `only` when it is not empty.  NaN values are neither smoothed
// nor averaged, but the walk goes through them (the accelerated SDF smooths
// its samples).  `ctx` (may be null) gets progress and is checked for
// cancellation.  `range`: the range Gaussian's deviation, in RMS deviations
// of the window's values (CGAL's 1.5).
void bilateral_smooth(const Adjacency& face_graph, std::vector<double>& values, int window = 0,
                      const Context* ctx = nullptr, std::span<const std::uint32_t> only = {}, double range = 1.5);
int default_window(std::size_t faces);

// The filter of every face, as above, where the window is small or the mesh
// coarse; where both the window and the mesh's own default window are
// kSampledWindow rings or more (meshes from 722k faces), the faster
// approximation of sdf/bilateral_sampled.h, within 0.5% of the smoothed
// values' range of this filter.
inline constexpr int kSampledWindow = 20;
void bilateral_smooth(const Mesh& mesh, const Adjacency& face_graph, std::vector<double>& values, int window = 0,
                      const Context* ctx = nullptr);

}  // namespace cgview::sdf
