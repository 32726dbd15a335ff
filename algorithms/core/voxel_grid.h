// VoxelGrid: a dense box of voxels, each a bit, a byte or a float.
//
// Voxel (i, j, k) is the cube [origin + (i, j, k) * voxel_size,
// origin + (i + 1, j + 1, k + 1) * voxel_size); its linear index is
// i + nx * (j + ny * k) (x fastest), the order of slices, VTK and OpenVDB's
// dense copies.  Bits are stored one per byte for speed of access.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "core/vec.h"

namespace cgview {

enum class VoxelType { bit, uint8, float32 };
// The 6 face neighbours, the 18 face-and-edge ones, or all 26.
enum class Connectivity { six = 6, eighteen = 18, twenty_six = 26 };

struct VoxelIndex {
  int i = 0, j = 0, k = 0;
  friend constexpr bool operator==(const VoxelIndex&, const VoxelIndex&) = default;
};

class VoxelGrid {
 public:
  VoxelGrid() = default;
  // Throws InvalidInput for a non-positive size or a grid over max_voxels voxels.
  VoxelGrid(std::array<int, 3> dims, Vec3 origin, double voxel_size, VoxelType type = VoxelType::bit,
            std::uint64_t max_voxels = std::uint64_t(1) << 31);

  std::array<int, 3> dims() const { return dims_; }
  Vec3 origin() const { return origin_; }
  double voxel_size() const { return voxel_size_; }
  VoxelType type() const { return type_; }
  std::size_t size() const { return std::size_t(dims_[0]) * dims_[1] * dims_[2]; }

  bool contains(VoxelIndex v) const {
    return v.i >= 0 && v.j >= 0 && v.k >= 0 && v.i < dims_[0] && v.j < dims_[1] && v.k < dims_[2];
  }
  std::size_t linear(VoxelIndex v) const {
    return std::size_t(v.i) + std::size_t(dims_[0]) * (v.j + std::size_t(dims_[1]) * v.k);
  }
  VoxelIndex unlinear(std::size_t n) const {
    return {int(n % dims_[0]), int((n / dims_[0]) % dims_[1]), int(n / (std::size_t(dims_[0]) * dims_[1]))};
  }
  Vec3 center(VoxelIndex v) const { return origin_ + Vec3{v.i + 0.5, v.j + 0.5, v.k + 0.5} * voxel_size_; }
  // The voxel holding point p (it may lie outside the grid: check contains()).
  VoxelIndex locate(Vec3 p) const;

  // Value access; bit and uint8 grids read as 0..255, float grids as stored.
  float get(VoxelIndex v) const;
  void set(VoxelIndex v, float value);
  bool occupied(VoxelIndex v) const { return contains(v) && get(v) != 0.f; }
  std::size_t count_occupied() const;

  const std::vector<std::uint8_t>& bytes() const { return bytes_; }  // bit and uint8 grids
  std::vector<std::uint8_t>& bytes() { return bytes_; }
  const std::vector<float>& floats() const { return floats_; }  // float grids
  std::vector<float>& floats() { return floats_; }

  // Offsets of the neighbours in the given connectivity (6, 18 or 26 of them).
  static const std::vector<VoxelIndex>& offsets(Connectivity c);
  // Calls f on each neighbour of v inside the grid.
  void for_each_neighbor(VoxelIndex v, Connectivity c, const std::function<void(VoxelIndex)>& f) const;

  // Labels the connected components of occupied voxels: label[i] is 0 for an
  // empty voxel and 1..count for the component of an occupied one.
  std::uint32_t components(Connectivity c, std::vector<std::uint32_t>& label) const;

 private:
  std::array<int, 3> dims_{0, 0, 0};
  Vec3 origin_{};
  double voxel_size_ = 1.0;
  VoxelType type_ = VoxelType::bit;
  std::vector<std::uint8_t> bytes_;
  std::vector<float> floats_;
};

}  // namespace cgview
