#include "core/voxel_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/errors.h"

namespace cgview {

VoxelGrid::VoxelGrid(std::array<int, 3> dims, Vec3 origin, double voxel_size, VoxelType type, std::uint64_t max_voxels)
    : dims_(dims), origin_(origin), voxel_size_(voxel_size), type_(type) {
  for (int d : dims)
    if (d <= 0) throw InvalidInput("voxel grid dimensions must be positive, got " + std::to_string(d));
  if (!(voxel_size > 0) || !std::isfinite(voxel_size)) throw InvalidInput("voxel size must be positive and finite");
  if (!is_finite(origin)) throw InvalidInput("voxel grid origin must be finite");
  // x * y < 2^62 cannot overflow; the product with z can, so compare by division.
  const std::uint64_t xy = std::uint64_t(dims[0]) * std::uint64_t(dims[1]), z = std::uint64_t(dims[2]);
  if (xy > max_voxels / z) {
    const bool fits = xy <= UINT64_MAX / z;
    throw InvalidInput("a " + std::to_string(dims[0]) + "x" + std::to_string(dims[1]) + "x" + std::to_string(dims[2]) +
                       " grid has " + (fits ? std::to_string(xy * z) : "over 2^64") + " voxels, over the limit of " +
                       std::to_string(max_voxels));
  }
  const std::uint64_t n = xy * z;
  if (type == VoxelType::float32) floats_.assign(n, 0.f);
  else bytes_.assign(n, 0);
}

VoxelIndex VoxelGrid::locate(Vec3 p) const {
  Vec3 q = (p - origin_) / voxel_size_;
  // Out of int's range (or NaN) the cast would be undefined: clamp far outside.
  auto cell = [](double t) {
    t = std::floor(t);
    return t >= -2e9 && t <= 2e9 ? int(t) : (t > 0 ? std::numeric_limits<int>::max() : std::numeric_limits<int>::min());
  };
  return {cell(q.x), cell(q.y), cell(q.z)};
}

float VoxelGrid::get(VoxelIndex v) const {
  const std::size_t n = linear(v);
  return type_ == VoxelType::float32 ? floats_[n] : float(bytes_[n]);
}

void VoxelGrid::set(VoxelIndex v, float value) {
  const std::size_t n = linear(v);
  if (type_ == VoxelType::float32) floats_[n] = value;
  else if (type_ == VoxelType::bit) bytes_[n] = value != 0.f ? 1 : 0;
  else bytes_[n] = std::uint8_t(std::clamp(value, 0.f, 255.f));
}

std::size_t VoxelGrid::count_occupied() const {
  std::size_t n = 0;
  if (type_ == VoxelType::float32) {
    for (float f : floats_) n += f != 0.f;
  } else {
    for (std::uint8_t b : bytes_) n += b != 0;
  }
  return n;
}

const std::vector<VoxelIndex>& VoxelGrid::offsets(Connectivity c) {
  static const auto make = [](int max_nonzero) {
    std::vector<VoxelIndex> out;
    for (int k = -1; k <= 1; ++k)
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
          const int nz = (i != 0) + (j != 0) + (k != 0);
          if (nz > 0 && nz <= max_nonzero) out.push_back({i, j, k});
        }
    return out;
  };
  static const std::vector<VoxelIndex> six = make(1), eighteen = make(2), all = make(3);
  return c == Connectivity::six ? six : (c == Connectivity::eighteen ? eighteen : all);
}

void VoxelGrid::for_each_neighbor(VoxelIndex v, Connectivity c, const std::function<void(VoxelIndex)>& f) const {
  for (const VoxelIndex& o : offsets(c)) {
    VoxelIndex w{v.i + o.i, v.j + o.j, v.k + o.k};
    if (contains(w)) f(w);
  }
}

std::uint32_t VoxelGrid::components(Connectivity c, std::vector<std::uint32_t>& label) const {
  label.assign(size(), 0);
  std::uint32_t count = 0;
  std::vector<std::size_t> stack;
  const auto& offs = offsets(c);
  for (std::size_t start = 0; start < size(); ++start) {
    if (label[start] || !occupied(unlinear(start))) continue;
    label[start] = ++count;
    stack.push_back(start);
    while (!stack.empty()) {
      const VoxelIndex v = unlinear(stack.back());
      stack.pop_back();
      for (const VoxelIndex& o : offs) {
        VoxelIndex w{v.i + o.i, v.j + o.j, v.k + o.k};
        if (!occupied(w)) continue;
        const std::size_t n = linear(w);
        if (!label[n]) {
          label[n] = count;
          stack.push_back(n);
        }
      }
    }
  }
  return count;
}

}  // namespace cgview
