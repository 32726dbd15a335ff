#include "skeleton/projection/simplify_skeleton.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

namespace cgview::skeleton {

void simplify(Skeleton& s, double merge_length, int iterations, const std::function<bool(const Vec3&)>& allowed) {
  // Collapse internal arcs (junction to junction) shorter than merge_length.
  for (bool changed = true; changed && merge_length > 0;) {
    changed = false;
    const std::vector<std::uint32_t> degree = node_degrees(s);
    for (const std::vector<Index>& b : skeleton_branches(s)) {
      if (b.size() < 2 || b.front() == b.back()) continue;
      if (degree[b.front()] < 3 || degree[b.back()] < 3) continue;
      double length = 0;
      for (std::size_t k = 1; k < b.size(); ++k) length += norm(s.nodes[b[k]] - s.nodes[b[k - 1]]);
      if (length >= merge_length) continue;
      // Every node of the arc becomes its first node, at the arc's middle.
      std::vector<Index> to(s.nodes.size());
      std::iota(to.begin(), to.end(), Index(0));
      for (Index n : b) to[n] = b.front();
      s.nodes[b.front()] = (s.nodes[b.front()] + s.nodes[b.back()]) * 0.5;
      std::vector<std::array<Index, 2>> edges;
      for (const auto& e : s.edges) {
        const Index a = to[e[0]], c = to[e[1]];
        if (a == c) continue;
        const bool dup = std::any_of(edges.begin(), edges.end(), [&](const std::array<Index, 2>& x) {
          return (x[0] == a && x[1] == c) || (x[0] == c && x[1] == a);
        });
        if (!dup) edges.push_back({a, c});
      }
      s.edges = std::move(edges);
      changed = true;
      break;  // branches and degrees changed: look again
    }
  }
  // A collapse inside a loop can leave a short spur (a node whose two edges
  // went to the same merged node): terminal branches shorter than
  // merge_length go (thin keeps none shorter than min_branch otherwise).
  if (merge_length > 0)
    prune_spurs(s, [&](const std::vector<Index>&, double length, Index) { return length < merge_length; });
  // Drop the nodes no edge uses any more, renumbering.
  {
    std::vector<std::int64_t> keep(s.nodes.size(), -1);
    std::vector<Vec3> nodes;
    for (const auto& e : s.edges)
      for (Index n : e)
        if (keep[n] < 0) keep[n] = std::int64_t(nodes.size()), nodes.push_back(s.nodes[n]);
    for (auto& e : s.edges) e = {Index(keep[e[0]]), Index(keep[e[1]])};
    if (!s.edges.empty()) s.nodes = std::move(nodes);
  }
  // Laplacian smoothing of the nodes inside branches (ends and junctions stay).
  const Adjacency adj = skeleton_adjacency(s);
  for (int it = 0; it < iterations; ++it) {
    std::vector<Vec3> next = s.nodes;
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      if (adj.degree(n) != 2) continue;
      const Vec3 mid = (s.nodes[adj.items[adj.offsets[n]]] + s.nodes[adj.items[adj.offsets[n] + 1]]) * 0.5;
      next[n] = s.nodes[n] + (mid - s.nodes[n]) * 0.5;
      if (allowed && !allowed(next[n])) next[n] = s.nodes[n];
    }
    s.nodes = std::move(next);
  }
}

}  // namespace cgview::skeleton
