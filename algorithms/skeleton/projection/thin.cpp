#include "skeleton/projection/thin.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "registry/registry.h"
#include "skeleton/projection/thinning.h"

namespace cgview::skeleton {

// The domain: the voxels with at least a fifth of the targets' votes (5% of
// the most, by default: half the voted voxels on the elephant, and the
// weakly voted rim that no path of the skeleton takes), unless that splits
// the targets into several components: then every voted voxel (the inside,
// as far as the views tell).  The targets: the voxels voted enough, which
// branches must reach.  The domain leaves the grid's border out (votes fall
// inside the bounding box, a voxel in from the border), so that the paths
// step by linear offsets.
Thinning::Thinning(const VoxelGrid& votes_, const std::vector<float>& radius, double threshold, double min_branch_)
    : votes(votes_), L{votes_.dims()}, I(votes_.floats()), step(steps26()) {
  top = I.empty() ? 0.f : *std::max_element(I.begin(), I.end());
  if (!(top > 0)) return;
  least_target = threshold * top;
  id.assign(L.size(), -1);
  offset = L.offsets();
  for (const double least : {0.2 * least_target, 0.0}) {
    for (std::size_t n : vox) id[n] = -1;
    vox.clear();
    for (int k = 1; k + 1 < L.d[2]; ++k)
      for (int j = 1; j + 1 < L.d[1]; ++j)
        for (std::size_t n = L.at(1, j, k), end = L.at(L.d[0] - 1, j, k); n < end; ++n)
          if (I[n] > least) id[n] = std::int32_t(vox.size()), vox.push_back(n);
    sets = UnionFind(vox.size());
    for (std::size_t c = 0; c < vox.size(); ++c)
      neighbours(
          c, [&](std::size_t m, std::size_t) { sets.unite(std::uint32_t(c), std::uint32_t(m)); }, ahead);
    std::int64_t first = -1;
    bool split = false;
    for (std::size_t c = 0; c < vox.size() && !split; ++c)
      if (I[vox[c]] >= least_target) {
        const std::int64_t r = sets.find(std::uint32_t(c));
        split = first >= 0 && r != first;
        first = r;
      }
    if (!split) break;
  }
  count = vox.size();
  target.resize(count);
  r2.resize(count);
  // The local radius: the mean radius of the medial discs that voted for
  // the voxel (the vote set itself is thinner).
  thick.assign(count, 1.f);
  vs = votes.voxel_size();
  for (std::size_t c = 0; c < count; ++c) {
    const float v = I[vox[c]];
    target[c] = v >= least_target;
    const double r = v / top + 0.01;
    r2[c] = r * r;
    if (!radius.empty()) thick[c] = float(radius[vox[c]] / vs);
  }
  targets_of.assign(count, 0);
  for (std::size_t c = 0; c < count; ++c) targets_of[sets.find(std::uint32_t(c))] += target[c];
  const Vec3 ext = Vec3{double(L.d[0]), double(L.d[1]), double(L.d[2])} * vs;
  diagonal = norm(ext);
  min_branch = min_branch_ * diagonal / vs;
  node_of.assign(count, -1);
  done.assign(count, 0);
  cost.assign(count, HUGE_VAL);
  along.assign(count, 0);
  parent.assign(count, -1);
  reached.assign(count, 0);
}

// A node sits at the vote-weighted centre of its voxel's 3x3x3
// neighbourhood: off the voxel lattice, towards the ridge of votes.
Index Thinning::node(std::size_t c) {
  if (node_of[c] < 0) {
    node_of[c] = std::int32_t(s.nodes.size());
    const std::size_t n = vox[c];
    Vec3 sum = votes.center(votes.unlinear(n)) * double(I[n]);
    double weight = I[n];
    L.neighbours(n, [&](std::size_t m, double) {
      sum += votes.center(votes.unlinear(m)) * double(I[m]);
      weight += I[m];
    });
    s.nodes.push_back(weight > 0 ? sum / weight : votes.center(votes.unlinear(n)));
  }
  return Index(node_of[c]);
}

bool Thinning::covered(std::size_t c) const {
  if (reached[c]) return true;
  const auto [i, j, k] = L.ijk(vox[c]);
  return std::any_of(balls.rbegin(), balls.rend(), [&, i = i, j = j, k = k](const std::array<int, 4>& b) {
    return (i - b[0]) * (i - b[0]) + (j - b[1]) * (j - b[1]) + (k - b[2]) * (k - b[2]) <= b[3];
  });
}

void Thinning::progress(double fraction, std::string_view stage) {
  if (!ctx) return;
  ctx->check_cancelled();
  if (fraction < reported + 0.01 && stage == reported_stage) return;
  reported = fraction;
  reported_stage = stage;
  ctx->progress(progress_from + (progress_to - progress_from) * fraction, stage);
}

void Thinning::grow_tree(bool tunnels, double branch_votes) {
  // Components in order of their most voted voxel.
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < count; ++c)
    if (target[c]) order.push_back(c);
  // Progress over [0.05, 0.7] of thin: the voxels settled and the targets
  // looked at for branches, against all there are (each is settled, and
  // looked at, once at most).
  std::size_t work = 0;
  const double all_work = double(count + order.size());
  const auto worked = [&] {
    if (++work % 4096 == 0) progress(0.05 + 0.65 * double(work) / all_work, "thinning");
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return I[vox[a]] > I[vox[b]]; });
  for (std::size_t root : order) {
    if (done[root]) continue;
    // The shortest paths stop once every target of the component has its
    // path, as only the targets' paths are used, leaving the weakly voted
    // rim of the votes unvisited; unless tunnels may close loops:
    // the trees then go on to meet around the tunnels (one of the
    // elephant's three loops is found only so).
    const std::size_t targets = targets_of[sets.find(std::uint32_t(root))];
    // Intensity-driven shortest paths from the root over the component
    // (Dijkstra, with a radix heap: a third less time than a binary heap).
    std::vector<std::size_t> members;
    RadixHeap q;
    cost[root] = 0;
    q.push(0, std::uint32_t(root));
    while (!q.empty() && (members.size() < targets || tunnels)) {
      const auto [c, n] = q.pop();
      if (c > cost[n] || done[n]) continue;
      done[n] = 1;
      worked();
      if (target[n]) members.push_back(n);
      // A settled neighbour is never improved (its cost is at most c), nor is
      // one of another component (not a neighbour): no need to ask `done`.
      neighbours(n, [&, c = c, n = n](std::size_t m, std::size_t k) {
        const double len = step[k].length;
        const double nc = c + len / r2[m];
        if (nc < cost[m]) {
          cost[m] = nc;
          parent[m] = std::int32_t(n);
          along[m] = along[n] + len;
          q.push(nc, std::uint32_t(m));
        }
      });
    }
    if (members.size() < 8) continue;  // a speck of votes
    // TEASAR: the farthest uncovered voxel gives a branch, back to the skeleton.
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) { return along[a] > along[b]; });
    double main_votes = -1;
    node(root);
    std::vector<std::size_t> path;
    for (std::size_t far : members) {
      worked();
      if (node_of[far] >= 0 || covered(far)) continue;
      path.clear();
      std::size_t n = far;
      while (node_of[n] < 0 && parent[n] >= 0) {
        path.push_back(n);
        n = std::size_t(parent[n]);
      }
      const std::size_t join = n;
      double mean = 0;
      for (std::size_t v : path) mean += I[vox[v]];
      mean /= double(std::max<std::size_t>(path.size(), 1));
      const bool keep = along[far] - along[join] >= min_branch && (main_votes < 0 || mean >= branch_votes * main_votes);
      if (keep) {
        if (main_votes < 0) main_votes = mean;
        Index prev = node(join);
        for (auto it = path.rbegin(); it != path.rend(); ++it) {
          const Index cur = node(*it);
          s.edges.push_back({prev, cur});
          prev = cur;
        }
      }
      // Cover the voxels within the local thickness of the path.
      for (std::size_t v : path) {
        const int r = int(std::ceil(1.5 * thick[v])) + 2;
        const auto [i, j, k] = L.ijk(vox[v]);
        balls.push_back({i, j, k, r * r});
      }
      reached[far] = 1;
    }
  }
}

void Thinning::tree_done() {
  voxel_of.assign(s.nodes.size(), 0);
  for (std::size_t c = 0; c < count; ++c)
    if (node_of[c] >= 0) voxel_of[std::size_t(node_of[c])] = c;
  degree = node_degrees(s);
  tree_edges = s.edges.size();
  closed.assign(s.nodes.size(), 0);
}

void Thinning::along_skeleton(Index from) {
  if (adj.offsets.empty() || adj_edges != s.edges.size()) adj = skeleton_adjacency(s), adj_edges = s.edges.size();
  g.assign(s.nodes.size(), HUGE_VAL);
  back.assign(s.nodes.size(), -1);
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  q.push({g[from] = 0, from});
  while (!q.empty()) {
    const auto [c, n] = q.top();
    q.pop();
    if (c > g[n]) continue;
    for (const std::uint32_t* m = adj.begin(n); m != adj.end(n); ++m) {
      const double nc = c + norm(s.nodes[*m] - s.nodes[n]) / vs;
      if (nc < g[*m]) q.push({g[*m] = nc, *m}), back[*m] = std::int32_t(n);
    }
  }
}

void Thinning::prune_after_loops() {
  if (s.edges.size() > tree_edges)
    prune_spurs(s, [&](const std::vector<Index>&, double length, Index tip) {
      // A spur that ends where a loop was closed is what remains of the
      // other side of the gap.
      const bool gap_side = tip < closed.size() && closed[tip];
      return length < min_branch * vs || gap_side;
    });
}

Skeleton thin(const VoxelGrid& votes, const std::vector<float>& radius, const SkeletonProjectionParams& p,
              int max_loops, const std::function<bool(const Vec3&)>& inside, const Context* ctx, double progress_from,
              double progress_to) {
  Thinning t(votes, radius, p.threshold, p.min_branch);
  t.ctx = ctx;
  t.progress_from = progress_from;
  t.progress_to = progress_to;
  t.progress(0.05, "thinning");
  if (!(t.top > 0)) return {};
  const bool tunnels = inside && max_loops >= 0;  // a closed mesh: its loops are its tunnels, at most its genus
  t.grow_tree(tunnels && max_loops > 0, p.branch_votes);
  if (t.s.edges.empty()) return std::move(t.s);
  // Loops.  The skeleton so far is a tree; a loop closes where the shape
  // has a tunnel.
  t.progress(0.7, "closing loops");
  t.tree_done();
  if (tunnels && max_loops > 0) t.close_tunnels(max_loops, inside);
  else if (!tunnels) t.close_gaps();
  t.progress(0.98, "closing loops");
  t.prune_after_loops();
  return std::move(t.s);
}

}  // namespace cgview::skeleton
