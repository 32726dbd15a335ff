// The loops of a closed mesh: its tunnels, at most its genus.
#include <algorithm>
#include <numeric>
#include <tuple>

#include "skeleton/projection/thinning.h"

namespace cgview::skeleton {

void Thinning::close_tunnels(int max_loops, const std::function<bool(const Vec3&)>& inside) {
  // Whether the loop (points in order) goes around a hole: more than 5%
  // of the samples of the triangles from its centre to its edges are
  // outside (21 a triangle: i / 6 of the way from the centre to the edge,
  // i = 1..6, at i points along it); the first sample past 5% answers.
  const auto around_a_hole = [&](const std::vector<Vec3>& loop) {
    Vec3 centre{};
    for (const Vec3& v : loop) centre += v;
    centre = centre / double(loop.size());
    const double enough = 0.05 * double(21 * loop.size());
    int out = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec3& a = loop[k];
      const Vec3& b = loop[(k + 1) % loop.size()];
      for (int i = 1; i <= 6; ++i)
        for (int j = 0; j < i; ++j)
          if (!inside(centre + (a - centre + (b - a) * (double(j) / i)) * (i / 6.0)) && ++out > enough) return true;
    }
    return false;
  };
  int loops = 0;
  // The tunnels.  The shortest-path trees meet themselves around a
  // tunnel: neighbouring voxels whose paths join the skeleton at nodes a
  // and b further apart along it than their two covering radii.  The
  // meetings across one tunnel touch one another, a cut through it: one
  // loop a cut, closed by the best voted meeting whose loop (its two
  // voxels' paths, the step between them and the skeleton's way from b
  // to a) goes around a hole, the best voted cuts first.
  std::vector<std::int32_t> joins(count, -1);  // the node where a settled voxel's path joins the skeleton
  std::vector<std::size_t> chain;
  for (std::size_t c = 0; c < count; ++c) {
    if (!done[c] || joins[c] >= 0) continue;
    chain.clear();
    std::size_t n = c;
    while (node_of[n] < 0 && joins[n] < 0 && parent[n] >= 0) chain.push_back(n), n = std::size_t(parent[n]);
    const std::int32_t j = node_of[n] >= 0 ? node_of[n] : joins[n];
    for (std::size_t v : chain) joins[v] = j;
    joins[n] = j;
  }
  struct Meeting {
    std::size_t u, v;  // the two voxels: u's path joins at a, v's at b
    Index a, b;
    float votes;  // the weaker voxel's
  };
  // The tree (a forest): each node's parent and its distance from its
  // root along it; two nodes are far apart if the way between them, up to
  // where their ways to the root meet, is longer than their two covers.
  std::vector<std::int32_t> up(s.nodes.size(), -2), level(s.nodes.size(), 0);
  std::vector<double> depth(s.nodes.size(), 0);
  {
    const Adjacency tree = skeleton_adjacency(s);
    std::vector<std::size_t> queue;
    for (std::size_t r = 0; r < s.nodes.size(); ++r) {
      if (up[r] != -2) continue;
      up[r] = -1;
      queue.assign(1, r);
      for (std::size_t q = 0; q < queue.size(); ++q)
        for (const std::uint32_t* m = tree.begin(queue[q]); m != tree.end(queue[q]); ++m)
          if (up[*m] == -2) {
            up[*m] = std::int32_t(queue[q]);
            level[*m] = level[queue[q]] + 1;
            depth[*m] = depth[queue[q]] + norm(s.nodes[*m] - s.nodes[queue[q]]) / vs;
            queue.push_back(*m);
          }
    }
  }
  const auto far_apart = [&](std::int32_t x, std::int32_t y) {
    const double limit = cover(voxel_of[std::size_t(x)]) + cover(voxel_of[std::size_t(y)]);
    for (double d = 0; x != y;) {
      if (level[std::size_t(x)] < level[std::size_t(y)]) std::swap(x, y);
      if (up[std::size_t(x)] < 0) return true;  // two trees
      d += depth[std::size_t(x)] - depth[std::size_t(up[std::size_t(x)])];
      if (d > limit) return true;
      x = up[std::size_t(x)];
    }
    return false;
  };
  // The answers for the pairs of nodes met last, by a hash of the pair
  // (neighbouring voxels mostly join at the same few pairs).
  std::vector<std::array<std::int32_t, 3>> known(4096, {-1, -1, 0});
  const auto far = [&](std::int32_t x, std::int32_t y) {
    std::array<std::int32_t, 3>& k = known[(std::uint32_t(x) * 2654435761u ^ std::uint32_t(y)) % known.size()];
    if (k[0] != x || k[1] != y) k = {x, y, far_apart(x, y)};
    return k[2] != 0;
  };
  std::vector<Meeting> meetings;
  for (std::size_t c = 0; c < count; ++c) {
    if (!done[c] || joins[c] < 0) continue;
    neighbours(
        c,
        [&](std::size_t m, std::size_t) {
          if (!done[m] || joins[m] < 0 || joins[m] == joins[c] ||
              !far(std::min(joins[c], joins[m]), std::max(joins[c], joins[m])))
            return;
          const std::size_t u = joins[c] < joins[m] ? c : m, v = u == c ? m : c;
          meetings.push_back({u, v, Index(joins[u]), Index(joins[v]), std::min(I[vox[u]], I[vox[v]])});
        },
        ahead);
  }
  std::vector<std::uint8_t> cut(count, 0);  // the voxels of far meetings
  for (const Meeting& x : meetings) cut[x.u] = cut[x.v] = 1;
  // The cuts: the meetings' voxels, joined where they touch (a meeting's
  // two voxels touch).
  UnionFind cuts(count);
  for (std::size_t c = 0; c < count; ++c)
    if (cut[c])
      neighbours(
          c,
          [&](std::size_t m, std::size_t) {
            if (cut[m]) cuts.unite(std::uint32_t(c), std::uint32_t(m));
          },
          ahead);
  std::vector<std::uint32_t> cut_of(meetings.size());
  for (std::size_t k = 0; k < meetings.size(); ++k) cut_of[k] = cuts.find(std::uint32_t(meetings[k].u));
  // The best voted meetings first; a cut's best voted meeting first.
  std::vector<std::size_t> best(meetings.size());
  std::iota(best.begin(), best.end(), std::size_t(0));
  std::sort(best.begin(), best.end(), [&](std::size_t i, std::size_t j) {
    const Meeting &x = meetings[i], &y = meetings[j];
    return std::tie(y.votes, x.a, x.b, x.u) < std::tie(x.votes, y.a, y.b, y.u);
  });
  // A settled voxel's path up to the skeleton as it is now (a loop closed
  // may have met it on its way), and the voxel where it joins.
  const auto path_of = [&](std::size_t c, std::vector<std::size_t>& path) {
    path.clear();
    for (; node_of[c] < 0; c = std::size_t(parent[c])) path.push_back(c);
    return c;
  };
  std::vector<std::size_t> pu, pv;
  std::vector<std::int8_t> holeless(count, 0);  // a cut's meetings found around no hole; -1 once it closed a loop
  for (std::size_t i = 0; i < best.size(); ++i) {
    const std::size_t k = best[i];
    if (loops >= max_loops) break;
    progress(0.75 + 0.23 * double(i) / double(best.size()), "closing loops");
    std::int8_t& failed = holeless[cut_of[k]];
    if (failed < 0 || failed >= 8) continue;  // closed, or no hole behind its 8 best voted meetings
    // Where the meeting's paths join the skeleton now: still far apart
    // along it?  (A meeting across a tunnel already closed now joins the
    // loop's own path on both sides.)
    const std::size_t ju = path_of(meetings[k].u, pu), jv = path_of(meetings[k].v, pv);
    const Index a = Index(node_of[ju]), b = Index(node_of[jv]);
    along_skeleton(a);
    if (!(g[b] > cover(ju) + cover(jv))) continue;
    // The loop: along the skeleton from b to a, then u's path down from
    // a, the step to v and v's path up to b.
    std::vector<Vec3> loop;
    for (std::int64_t n = b; n >= 0; n = back[std::size_t(n)]) loop.push_back(s.nodes[std::size_t(n)]);
    for (auto it = pu.rbegin(); it != pu.rend(); ++it) loop.push_back(votes.center(votes.unlinear(vox[*it])));
    for (std::size_t c : pv) loop.push_back(votes.center(votes.unlinear(vox[c])));
    if (!around_a_hole(loop)) {
      ++failed;
      continue;
    }
    // The tree's ends within two of their covering radii of a or b along
    // it (g: the walk from a, then from b) are what remains past the
    // loop: spurs.
    const auto mark_spurs = [&] {
      for (std::size_t f = 0; f < degree.size(); ++f)
        if (degree[f] == 1 && g[f] <= 2 * cover(voxel_of[f])) closed[f] = 1;
    };
    mark_spurs();
    along_skeleton(b);
    mark_spurs();
    // The loop's edges are all new (its voxels were no nodes, and a and b
    // are far apart).
    Index prev = a;
    for (auto it = pu.rbegin(); it != pu.rend(); ++it) {
      const Index n = node(*it);
      s.edges.push_back({prev, n});
      prev = n;
    }
    for (std::size_t c : pv) {
      const Index n = node(c);
      s.edges.push_back({prev, n});
      prev = n;
    }
    s.edges.push_back({prev, b});
    failed = -1;
    ++loops;
  }
}

}  // namespace cgview::skeleton
