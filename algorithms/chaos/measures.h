// Measures used in the mesh and point-cloud encryption and steganography
// literature, on vertex positions.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/mesh.h"

namespace cgview::chaos {

// Pearson correlation of adjacent coordinates along the vertex order:
// (c_i, c_{i+1}) for i = 0..n-2, one value per axis (x, y, z).  0 for fewer
// than 3 vertices or a constant axis.
std::array<double, 3> adjacent_correlation(const std::vector<Vec3>& points);

// Symmetric Hausdorff distance between two point sets (vertex to vertex,
// nearest neighbours by a kd-tree; not the surface-to-surface distance).
// Both sets non-empty.
double hausdorff_vertices(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// Share of coordinates of a whose bits differ from b's at the same index
// (a and b of the same size; float32 comparison).  1 when sizes differ.
double changed_share(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// Displacement of corresponding vertices (same size): RMS and max of |a_i - b_i|.
struct Displacement {
  double rms = 0, max = 0;
};
Displacement displacement(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// SNR in dB of the distortion b - a against the signal a - centroid(a), as in
// mesh watermarking (Cho et al. 2007): 10 log10(sum |a_i - c|^2 / sum |b_i - a_i|^2);
// +infinity when b == a.
double snr_db(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

// The key with the lowest bit of its last byte flipped (for key sensitivity).
std::string flip_one_bit(std::string key);

}  // namespace cgview::chaos
