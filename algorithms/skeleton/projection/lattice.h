// The voxel lattice the thinning walks: 26-neighbour steps, linear indices,
// and a radix heap for its shortest paths.  Private to skeleton/projection.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace cgview::skeleton {

// The 26 neighbour offsets and their lengths (in voxels).
struct Step {
  int di, dj, dk;
  double length;
};
inline const std::vector<Step>& steps26() {
  static const std::vector<Step> s = [] {
    std::vector<Step> out;
    for (int k = -1; k <= 1; ++k)
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i)
          if (i || j || k) out.push_back({i, j, k, std::sqrt(double(i * i + j * j + k * k))});
    return out;
  }();
  return s;
}

// A voxel set as linear indices into a grid of dims d, with neighbour lookup.
struct Lattice {
  std::array<int, 3> d;
  std::size_t size() const { return std::size_t(d[0]) * d[1] * d[2]; }
  std::size_t at(int i, int j, int k) const {
    return std::size_t(i) + std::size_t(d[0]) * (std::size_t(j) + std::size_t(d[1]) * k);
  }
  std::array<int, 3> ijk(std::size_t n) const {
    return {int(n % d[0]), int((n / d[0]) % d[1]), int(n / (std::size_t(d[0]) * d[1]))};
  }
  // The 26 neighbours as linear offsets (with steps26's lengths), for
  // voxels off the grid's border.
  std::vector<std::ptrdiff_t> offsets() const {
    std::vector<std::ptrdiff_t> o;
    for (const Step& s : steps26()) o.push_back(s.di + std::ptrdiff_t(d[0]) * (s.dj + std::ptrdiff_t(d[1]) * s.dk));
    return o;
  }
  // Calls f(neighbour, step length) for the in-grid 26-neighbours.
  template <class F>
  void neighbours(std::size_t n, F&& f) const {
    const auto [i, j, k] = ijk(n);
    for (const Step& s : steps26()) {
      const int a = i + s.di, b = j + s.dj, c = k + s.dk;
      if (a < 0 || b < 0 || c < 0 || a >= d[0] || b >= d[1] || c >= d[2]) continue;
      f(at(a, b, c), s.length);
    }
  }
};

// A radix heap (Ahuja, Mehlhorn, Orlin, Tarjan 1990) for Dijkstra's
// monotone keys: non-negative doubles, whose bits order as they do.  An item
// sits in the bucket of the highest bit where its key differs from the last
// key popped; popping refills bucket 0 from the first non-empty one.
class RadixHeap {
 public:
  bool empty() const { return size_ == 0; }
  void push(double key, std::uint32_t value) {
    const std::uint64_t k = bits(key);
    buckets_[bucket(k)].push_back({k, value});
    ++size_;
  }
  // The least key and its value, removed.
  std::pair<double, std::uint32_t> pop() {
    if (buckets_[0].empty()) {
      std::size_t i = 1;
      while (buckets_[i].empty()) ++i;
      last_ = std::min_element(buckets_[i].begin(), buckets_[i].end())->first;
      for (const auto& item : buckets_[i]) buckets_[bucket(item.first)].push_back(item);
      buckets_[i].clear();
    }
    const auto item = buckets_[0].back();
    buckets_[0].pop_back();
    --size_;
    return {std::bit_cast<double>(item.first), item.second};
  }

 private:
  static std::uint64_t bits(double key) { return std::bit_cast<std::uint64_t>(key); }
  std::size_t bucket(std::uint64_t k) const { return std::size_t(std::bit_width(k ^ last_)); }
  std::array<std::vector<std::pair<std::uint64_t, std::uint32_t>>, 65> buckets_;
  std::uint64_t last_ = 0;
  std::size_t size_ = 0;
};

}  // namespace cgview::skeleton
