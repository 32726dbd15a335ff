// The loops of a mesh that is not closed: gaps between an end and a far part
// of the skeleton, through voted voxels.
#include <algorithm>
#include <cmath>

#include "skeleton/projection/thinning.h"

namespace cgview::skeleton {

void Thinning::close_gaps() {
  // Other meshes: an end next to (through voted voxels: 90% of the
  // samples every quarter voxel, as votes are sparse) a part of the
  // skeleton far along it closes a loop, twice as far as its branch
  // covers; another end is preferred (the two close it cleanly), and the
  // ends within that reach are its gap's other side: not a gap again.
  struct Gap {
    Index e, n;
    double reach;
  };
  std::vector<Gap> gaps;
  std::vector<std::uint8_t> taken(degree.size(), 0);
  const auto beside = [&](const Gap& x, std::vector<std::uint8_t>& ends) {
    for (std::size_t f = 0; f < degree.size(); ++f)
      if (degree[f] == 1 && norm(s.nodes[f] - s.nodes[x.e]) / vs <= x.reach) ends[f] = 1;
  };
  for (std::size_t e = 0; e < degree.size(); ++e) {
    progress(0.7 + 0.15 * double(e) / double(degree.size()), "closing loops");
    if (degree[e] != 1 || taken[e]) continue;
    const double reach = 2 * cover(voxel_of[e]);
    along_skeleton(Index(e));
    std::size_t best = e;
    double best_d = HUGE_VAL;
    bool best_is_end = false;
    for (std::size_t n = 0; n < degree.size(); ++n) {
      const double d = norm(s.nodes[n] - s.nodes[e]) / vs;
      const bool is_end = degree[n] == 1;
      if (d > reach || g[n] < 4 * reach || (best_is_end && !is_end) || (is_end == best_is_end && d >= best_d)) continue;
      const int samples = int(std::floor(4 * std::max(d, 1.0))) + 1;
      int voted = 0;
      for (int k = 0; k < samples; ++k) {
        const VoxelIndex c = votes.locate(s.nodes[e] + (s.nodes[n] - s.nodes[e]) * (double(k) / (samples - 1)));
        voted += votes.contains(c) && I[votes.linear(c)] > 0;
      }
      if (voted >= 0.9 * samples) best = n, best_d = d, best_is_end = is_end;
    }
    if (best == e) continue;
    gaps.push_back({Index(e), Index(best), reach});
    beside(gaps.back(), taken);
  }
  // Each gap closes along the ridge of votes: the intensity-driven
  // shortest path between its two voxels, not through the skeleton (a
  // path touching it on its way would close small loops there too).
  std::fill(cost.begin(), cost.end(), HUGE_VAL);
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    progress(0.85 + 0.13 * double(i) / double(gaps.size()), "closing loops");
    const Gap& x = gaps[i];
    const std::size_t from = voxel_of[x.e], to = voxel_of[x.n];
    std::vector<std::size_t> touched{from};
    RadixHeap q;
    cost[from] = 0;
    parent[from] = -1;
    q.push(0, std::uint32_t(from));
    while (!q.empty()) {
      const auto [cn, c] = q.pop();
      if (cn > cost[c]) continue;
      if (c == to) {
        // All new edges: the path's voxels were no nodes, and the gap's
        // two nodes are far apart along the skeleton.
        Index prev = x.n;
        for (std::int64_t m = parent[to]; m >= 0 && std::size_t(m) != from; m = parent[std::size_t(m)]) {
          const Index n = node(std::size_t(m));
          s.edges.push_back({prev, n});
          prev = n;
        }
        s.edges.push_back({prev, x.e});
        beside(x, closed);
        break;
      }
      neighbours(c, [&, cn = cn, c = c](std::size_t m, std::size_t k) {
        if (node_of[m] >= 0 && m != to) return;
        const double nc = cn + step[k].length / r2[m];
        if (nc >= cost[m]) return;
        if (cost[m] == HUGE_VAL) touched.push_back(m);
        cost[m] = nc;
        parent[m] = std::int32_t(c);
        q.push(nc, std::uint32_t(m));
      });
    }
    for (std::size_t m : touched) cost[m] = HUGE_VAL;
  }
}

}  // namespace cgview::skeleton
