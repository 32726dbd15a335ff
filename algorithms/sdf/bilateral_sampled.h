// The SDF's bilateral filter (sdf/bilateral_filter.h) for large windows,
// approximately: exact windows at sites a few rings apart, interpolated.
//
// - Sites: every face within `spacing` rings of one (about 1 face in 8 at
//   3 rings); each face belongs to its nearest site's region.
// - Per site, its window exactly (the faces within `window` rings, NaN
//   skipped), binned on `bins` values over the values' range, each bin as
//   its faces' mean value m_b and spatial weight w_b = sum exp(-ring^2 /
//   (2 (window/2)^2)); then, for each centre value c on the grid's nodes
//   that the faces nearby have, the value the exact filter gives a face
//   with value c and that window:
//     sum_b w_b e_b m_b / sum_b w_b e_b,  e_b = exp(-(m_b - c)^2 / (2 (1.5 s)^2)),
//   s^2 = (sum x^2 - 2 c sum x + N c^2) / N over the window (unweighted,
//   as the exact filter's s).
// - Per face f with value c: those values at c (linear between nodes) at
//   its own site and the sites whose regions touch it, and at f the
//   weighted least-squares plane through them over the face centres'
//   offsets, its weights 1 / (d^2 / r^2 + 1/4) (r: the distance to the
//   face's neighbours, about a ring).
// - A site takes its own window's value at its own value.
// - A face where the sites leave that plane by more than `tolerance` of the
//   smoothed values' range less the plane's change over `slope_rings`
//   rings takes its own window instead, walked and binned as a site's and
//   evaluated at its own value: a face's window differs from its sites' in
//   shape, not only in place (rings are not circles), and the difference
//   is about the values' change over a ring.  The bins alone move a face by
//   0.046% of the range at most (every face of the 1.42M-face mesh below
//   taken so).
//
// Its difference from the exact filter, as a fraction of the smoothed
// values' range: at most 0.36% (mean 0.02%) on the 1.42M-face mesh of
// bench/sdf_smooth_bench.cpp (window 27, 10.5% of the faces on their own
// windows), 0.42% on refined_elephant subdivided once with window 20 (26%
// on their own); where the sites fall moves these by a few hundredths of a
// percent.  On coarser meshes the windows change shape faster than the
// sites follow (0.5-1% on 90-140k faces with window 20, half of them on
// their own windows): bilateral_smooth takes it only where a mesh's own
// default window is large (sdf/bilateral_filter.h).
#pragma once

#include <cstddef>
#include <vector>

#include "core/mesh.h"

namespace cgview {
class Context;
}

namespace cgview::sdf {

struct SampledFilterParams {
  int spacing = 3;           // rings from a face to its nearest site, at most
  int bins = 128;            // nodes of the value grid
  double tolerance = 0.007;  // of the smoothed values' range
  double slope_rings = 1.0;  // rings of the values' change counted against it
};

struct SampledFilterStats {
  std::size_t sites = 0;
  std::size_t exact = 0;  // faces from their own window, not the sites'
};

// Smooths `values` (one per face of `mesh`; `face_graph` its face graph) in
// place as bilateral_smooth does over all faces, approximately as above.
// NaN values stay NaN and are walked through.  `window` <= 0 takes
// default_window.
void bilateral_smooth_sampled(const Mesh& mesh, const Adjacency& face_graph, std::vector<double>& values,
                              int window = 0, const Context* ctx = nullptr, const SampledFilterParams& p = {},
                              SampledFilterStats* stats = nullptr);

}  // namespace cgview::sdf
