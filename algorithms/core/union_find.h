// Disjoint sets over 0 .. n-1 (union-find with path halving); each set's
// representative is its lowest member.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace cgview {

struct UnionFind {
  std::vector<std::uint32_t> parent;
  explicit UnionFind(std::size_t n = 0) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  // Each member's set numbered 0 .. count-1 in order of the sets' lowest
  // members; returns the count.
  std::uint32_t labels(std::vector<std::uint32_t>& label) {
    const std::uint32_t none = UINT32_MAX;
    std::vector<std::uint32_t> of_root(parent.size(), none);
    label.resize(parent.size());
    std::uint32_t count = 0;
    for (std::uint32_t v = 0; v < parent.size(); ++v) {
      const std::uint32_t r = find(v);
      if (of_root[r] == none) of_root[r] = count++;
      label[v] = of_root[r];
    }
    return count;
  }
};

}  // namespace cgview
