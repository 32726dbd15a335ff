#include "skeleton/skeleton_projection.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <numeric>
#include <queue>
#include <thread>

#include "core/mesh_report.h"
#include "rays/ray_caster.h"
#include "registry/registry.h"
#include "render/renderer.h"
#include "render/views.h"

namespace cgview::skeleton {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

void need(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput(what);
}

// The 26 neighbour offsets and their lengths (in voxels).
struct Step {
  int di, dj, dk;
  double length;
};
const std::vector<Step>& steps26() {
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
  std::size_t at(int i, int j, int k) const { return std::size_t(i) + std::size_t(d[0]) * (std::size_t(j) + std::size_t(d[1]) * k); }
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
  bool on_border(std::size_t n) const {
    const auto [i, j, k] = ijk(n);
    return i == 0 || j == 0 || k == 0 || i == d[0] - 1 || j == d[1] - 1 || k == d[2] - 1;
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

}  // namespace

void ProjectionParams::check() const {
  need(views >= 2 && views <= 1000 && views % 2 == 0,
       "parameter 'views': " + std::to_string(views) + " must be an even number in 2..1000 (antipodal pairs)");
  need(image >= 32 && image <= 2048, "parameter 'image': " + std::to_string(image) + " is outside 32..2048");
  need(grid >= 16 && grid <= 512, "parameter 'grid': " + std::to_string(grid) + " is outside 16..512");
  need(min_radius >= 0 && min_radius <= 100, "parameter 'min_radius' is outside 0..100");
  need(threshold > 0 && threshold < 1, "parameter 'threshold' must be in (0, 1)");
  need(min_branch >= 0 && min_branch < 1, "parameter 'min_branch' must be in [0, 1)");
  need(branch_votes >= 0 && branch_votes <= 1, "parameter 'branch_votes' must be in [0, 1]");
  need(merge_distance >= 0 && merge_distance < 1, "parameter 'merge_distance' must be in [0, 1)");
  need(smoothing >= 0 && smoothing <= 1000, "parameter 'smoothing' is outside 0..1000");
  need(contexts >= 1 && contexts <= 64, "parameter 'contexts' is outside 1..64");
}

std::vector<std::uint16_t> chamfer_34(const std::vector<std::uint8_t>& mask, int w, int h) {
  constexpr std::uint16_t far = 60000;
  std::vector<std::uint16_t> d(std::size_t(w) * h, 0);
  const auto in = [&](int x, int y) { return x >= 0 && y >= 0 && x < w && y < h; };
  const auto get = [&](int x, int y) -> int { return in(x, y) ? d[std::size_t(y) * w + x] : 0; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!mask[std::size_t(y) * w + x]) continue;
      int v = far;
      v = std::min({v, get(x - 1, y) + 3, get(x, y - 1) + 3, get(x - 1, y - 1) + 4, get(x + 1, y - 1) + 4});
      d[std::size_t(y) * w + x] = std::uint16_t(v);
    }
  for (int y = h - 1; y >= 0; --y)
    for (int x = w - 1; x >= 0; --x) {
      if (!mask[std::size_t(y) * w + x]) continue;
      int v = d[std::size_t(y) * w + x];
      v = std::min({v, get(x + 1, y) + 3, get(x, y + 1) + 3, get(x + 1, y + 1) + 4, get(x - 1, y + 1) + 4});
      d[std::size_t(y) * w + x] = std::uint16_t(v);
    }
  return d;
}

std::vector<std::uint8_t> medial_axis(const std::vector<std::uint16_t>& dt, int w, int h, int min_radius) {
  std::vector<std::uint8_t> axis(dt.size(), 0);
  const int least = std::max(1, 3 * min_radius);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int v = dt[std::size_t(y) * w + x];
      if (v < least) continue;
      bool maximal = true;
      for (int dy = -1; dy <= 1 && maximal; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!dx && !dy) continue;
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          if (dt[std::size_t(ny) * w + nx] >= v + ((dx && dy) ? 4 : 3)) {
            maximal = false;
            break;
          }
        }
      axis[std::size_t(y) * w + x] = maximal;
    }
  return axis;
}

VoxelGrid vote(const std::vector<render::ViewCapture>& views, const BBox& box, const ProjectionParams& p,
               std::vector<float>* radius, const Context* ctx) {
  const Vec3 size = box.size();
  const double longest = std::max({size.x, size.y, size.z, 1e-12});
  const double vs = longest / p.grid;
  const std::array<int, 3> dims{int(std::ceil(size.x / vs)) + 2, int(std::ceil(size.y / vs)) + 2, int(std::ceil(size.z / vs)) + 2};
  VoxelGrid grid(dims, box.min - Vec3{vs, vs, vs}, vs, VoxelType::float32);
  const int threads = std::max(1, std::min<int>(int(std::thread::hardware_concurrency()), int(views.size())));
  std::vector<std::vector<float>> partial(threads, std::vector<float>(grid.size(), 0.f));
  std::vector<std::vector<float>> partial_radius(threads, std::vector<float>(radius ? grid.size() : 0, 0.f));
  auto work = [&](int t) {
    std::vector<float>& acc = partial[t];
    std::vector<float>& acc_radius = partial_radius[t];
    for (std::size_t v = std::size_t(t); v < views.size(); v += std::size_t(threads)) {
      if (t == 0 && ctx && ctx->cancelled()) return;
      const render::ViewCapture& a = views[v];
      const render::ViewCapture& b = views[v ^ 1];  // its antipode
      const int w = a.camera.width, h = a.camera.height;
      const std::vector<std::uint16_t> dt = chamfer_34(a.silhouette, w, h);
      const std::vector<std::uint8_t> axis = medial_axis(dt, w, h, p.min_radius);
      const Vec3 dir = a.camera.forward();
      const double pixel = a.camera.pixel_size_at(0);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t i = std::size_t(y) * w + x;
          if (!axis[i] || a.depth[i] >= 1.f) continue;
          const Vec3 entry = a.camera.unproject(x + 0.5, y + 0.5, a.depth[i]);
          const double radius_world = dt[i] / 3.0 * pixel;
          double length = 2 * radius_world;
          const Vec3 q = b.camera.project(entry);
          const int bx = int(std::floor(q.x)), by = int(std::floor(q.y));
          if (bx >= 0 && by >= 0 && bx < w && by < h && b.depth[std::size_t(by) * w + bx] < 1.f) {
            const Vec3 exit = b.camera.unproject(q.x, q.y, b.depth[std::size_t(by) * w + bx]);
            length = std::min(length, std::max(0.0, dot(exit - entry, dir)));
          }
          // A straight ray leaves a voxel for good: a sample in the voxel of
          // the one before is the same vote.
          std::size_t last = SIZE_MAX;
          for (double s = 0; s <= length; s += vs / 2) {
            const VoxelIndex c = grid.locate(entry + dir * s);
            if (!grid.contains(c)) continue;
            const std::size_t n = grid.linear(c);
            if (n == last) continue;
            last = n;
            acc[n] += 1.f;
            if (radius) acc_radius[n] += float(radius_world);
          }
        }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work, t);
  work(0);
  for (auto& th : pool) th.join();
  if (ctx) ctx->check_cancelled();
  std::vector<float>& out = grid.floats();
  for (const auto& part : partial)
    for (std::size_t n = 0; n < out.size(); ++n) out[n] += part[n];
  if (radius) {
    radius->assign(grid.size(), 0.f);
    for (const auto& part : partial_radius)
      for (std::size_t n = 0; n < out.size(); ++n) (*radius)[n] += part[n];
    for (std::size_t n = 0; n < out.size(); ++n)
      if (out[n] > 0) (*radius)[n] /= out[n];
  }
  return grid;
}

Skeleton thin(const VoxelGrid& votes, const std::vector<float>& radius, const ProjectionParams& p, int max_loops,
              const std::function<bool(const Vec3&)>& inside) {
  const Lattice L{votes.dims()};
  const std::vector<float>& I = votes.floats();
  const float top = I.empty() ? 0.f : *std::max_element(I.begin(), I.end());
  Skeleton s;
  if (!(top > 0)) return s;
  // The domain: every voted voxel (the inside, as far as the views tell);
  // the targets: the voxels voted enough, which branches must reach.
  std::vector<std::uint8_t> mask(L.size(), 0), target(L.size(), 0);
  // The mask leaves the grid's border out (votes fall inside the bounding
  // box, a voxel in from the border), so that the paths below step by
  // linear offsets.
  for (std::size_t n = 0; n < L.size(); ++n) {
    if (!(I[n] > 0) || L.on_border(n)) continue;
    mask[n] = 1;
    target[n] = I[n] >= p.threshold * top;
  }
  // The intensity weight of a step onto a voxel.
  const auto r2 = [&](std::size_t m) {
    const double r = I[m] / top + 0.01;
    return r * r;
  };
  const std::vector<std::ptrdiff_t> offset = L.offsets();
  const std::vector<Step>& step = steps26();
  const double vs = votes.voxel_size();
  // The local radius of the shape, in voxels: the mean radius of the medial
  // discs that voted for the voxel (the vote set itself is thinner).
  std::vector<float> thick(L.size(), 0.f);
  for (std::size_t n = 0; n < L.size(); ++n) thick[n] = radius.empty() ? 1.f : float(radius[n] / vs);
  const Vec3 ext = Vec3{double(L.d[0]), double(L.d[1]), double(L.d[2])} * vs;
  const double diagonal = norm(ext);
  const double min_branch = p.min_branch * diagonal / vs;  // in voxels

  std::vector<std::int32_t> node_of(L.size(), -1);  // skeleton node of a voxel (grids up to 512³ fit 32 bits)
  // A node sits at the vote-weighted centre of its voxel's 3x3x3
  // neighbourhood: off the voxel lattice, towards the ridge of votes.
  const auto node = [&](std::size_t n) {
    if (node_of[n] < 0) {
      node_of[n] = std::int32_t(s.nodes.size());
      Vec3 sum = votes.center(votes.unlinear(n)) * double(I[n]);
      double weight = I[n];
      L.neighbours(n, [&](std::size_t m, double) {
        sum += votes.center(votes.unlinear(m)) * double(I[m]);
        weight += I[m];
      });
      s.nodes.push_back(weight > 0 ? sum / weight : votes.center(votes.unlinear(n)));
    }
    return Index(node_of[n]);
  };
  std::vector<std::uint8_t> done(L.size(), 0);  // voxels of components already processed
  std::vector<double> cost(L.size(), HUGE_VAL), along(L.size(), 0);
  std::vector<std::int32_t> parent(L.size(), -1);
  std::vector<std::uint8_t> covered(L.size(), 0), seen(L.size(), 0);

  // Components in order of their most voted voxel.
  std::vector<std::size_t> order;
  for (std::size_t n = 0; n < L.size(); ++n)
    if (target[n]) order.push_back(n);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return I[a] > I[b]; });
  for (std::size_t root : order) {
    if (done[root]) continue;
    // The component's targets, counted (a breadth-first walk is cheaper than
    // the shortest paths): those stop once every target has its path, as
    // only the targets' paths are used, leaving the weakly voted rim of the
    // votes unvisited.
    std::size_t targets = 0;
    {
      std::vector<std::size_t> stack{root};
      seen[root] = 1;
      while (!stack.empty()) {
        const std::size_t n = stack.back();
        stack.pop_back();
        targets += target[n];
        for (std::size_t k = 0; k < 26; ++k) {
          const std::size_t m = std::size_t(std::ptrdiff_t(n) + offset[k]);
          if (mask[m] && !seen[m]) seen[m] = 1, stack.push_back(m);
        }
      }
    }
    // Intensity-driven shortest paths from the root over the component.
    std::vector<std::size_t> members;
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    cost[root] = 0;
    q.push({0, root});
    while (!q.empty() && members.size() < targets) {
      const auto [c, n] = q.top();
      q.pop();
      if (c > cost[n] || done[n]) continue;
      done[n] = 1;
      if (target[n]) members.push_back(n);
      for (std::size_t k = 0; k < 26; ++k) {
        const std::size_t m = std::size_t(std::ptrdiff_t(n) + offset[k]);
        if (!mask[m] || done[m]) continue;
        const double len = step[k].length;
        const double nc = c + len / r2(m);
        if (nc < cost[m]) {
          cost[m] = nc;
          parent[m] = std::int32_t(n);
          along[m] = along[n] + len;
          q.push({nc, m});
        }
      }
    }
    if (members.size() < 8) continue;  // a speck of votes
    // TEASAR: the farthest uncovered voxel gives a branch, back to the skeleton.
    std::sort(members.begin(), members.end(), [&](std::size_t a, std::size_t b) { return along[a] > along[b]; });
    double main_votes = -1;
    node(root);
    std::vector<std::size_t> path;
    for (std::size_t far : members) {
      if (covered[far] || node_of[far] >= 0) continue;
      path.clear();
      std::size_t n = far;
      while (node_of[n] < 0 && parent[n] >= 0) {
        path.push_back(n);
        n = std::size_t(parent[n]);
      }
      const std::size_t join = n;
      double mean = 0;
      for (std::size_t v : path) mean += I[v];
      mean /= double(std::max<std::size_t>(path.size(), 1));
      const bool keep = along[far] - along[join] >= min_branch && (main_votes < 0 || mean >= p.branch_votes * main_votes);
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
        const auto [i, j, k] = L.ijk(v);
        for (int c = std::max(0, k - r); c <= std::min(L.d[2] - 1, k + r); ++c)
          for (int b = std::max(0, j - r); b <= std::min(L.d[1] - 1, j + r); ++b) {
            // The ball's row: |a - i| <= the integer square root of what is left.
            const int left = r * r - (b - j) * (b - j) - (c - k) * (c - k);
            if (left < 0) continue;
            int dx = int(std::sqrt(double(left)));
            while (dx * dx > left) --dx;
            while ((dx + 1) * (dx + 1) <= left) ++dx;
            const int a0 = std::max(0, i - dx), a1 = std::min(L.d[0] - 1, i + dx);
            std::fill(covered.begin() + std::ptrdiff_t(L.at(a0, b, c)), covered.begin() + std::ptrdiff_t(L.at(a1, b, c)) + 1, 1);
          }
      }
      covered[far] = 1;
    }
  }
  if (s.edges.empty()) return s;

  // Loops: an end of the skeleton next to (through voted voxels) a part of it
  // that is far along the skeleton closes a tunnel.
  const Adjacency adj = skeleton_adjacency(s);
  const std::vector<std::uint32_t> degree = node_degrees(s);
  std::vector<std::size_t> voxel_of(s.nodes.size());
  for (std::size_t n = 0; n < L.size(); ++n)
    if (node_of[n] >= 0) voxel_of[std::size_t(node_of[n])] = n;
  std::vector<std::array<Index, 2>> closing;
  std::vector<std::uint8_t> closed(s.nodes.size(), 0);  // ends already used by a loop
  // Tunnels (with the solid and its genus): an end looks for a gap twice as
  // far, through the solid rather than the sparse votes; the gap closes a
  // loop only if that loop goes around a hole (the fan of triangles from
  // its centre crosses the outside), and at most `max_loops` gaps close,
  // shortest first.
  const bool tunnels = bool(inside) && max_loops >= 0;
  struct Gap {
    Index e, n;
    double d;
  };
  std::vector<Gap> gaps;
  const auto close_gap = [&](Index e, Index n, double reach) {
    closing.push_back({e, n});
    // The other end of the same gap closes the same loop: not twice.
    for (std::size_t f = 0; f < s.nodes.size(); ++f)
      if (degree[f] == 1 && norm(s.nodes[f] - s.nodes[e]) / vs <= reach) closed[f] = 1;
  };
  // Whether the loop (nodes in order) is around a hole: samples of the
  // triangles from its centre to each of its edges, more than 5% outside.
  const auto around_a_hole = [&](const std::vector<Vec3>& loop) {
    Vec3 centre{};
    for (const Vec3& v : loop) centre += v;
    centre = centre / double(loop.size());
    int out = 0, all = 0;
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Vec3& a = loop[k];
      const Vec3& b = loop[(k + 1) % loop.size()];
      for (int i = 1; i <= 6; ++i)  // i / 6 of the way from the centre to the edge a b
        for (int j = 0; j < i; ++j, ++all) out += !inside(centre + (a - centre + (b - a) * (double(j) / i)) * (i / 6.0));
    }
    return out > 0.05 * all;
  };
  for (std::size_t e = 0; e < s.nodes.size() && !(tunnels && max_loops == 0); ++e) {
    if (degree[e] != 1 || closed[e]) continue;
    // Twice as far as a branch's covering reaches (four times for tunnels).
    const double cover = 1.5 * thick[voxel_of[e]] + 2;
    const double reach = (tunnels ? 4 : 2) * cover;
    // Distances along the skeleton from e (Dijkstra over its edges).
    std::vector<double> g(s.nodes.size(), HUGE_VAL);
    std::vector<std::int32_t> back(s.nodes.size(), -1);
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    q.push({g[e] = 0, e});
    while (!q.empty()) {
      const auto [c, n] = q.top();
      q.pop();
      if (c > g[n]) continue;
      for (const std::uint32_t* m = adj.begin(n); m != adj.end(n); ++m) {
        const double nc = c + norm(s.nodes[*m] - s.nodes[n]) / vs;
        if (nc < g[*m]) q.push({g[*m] = nc, *m}), back[*m] = std::int32_t(n);
      }
    }
    if (tunnels) {
      std::size_t best = e;
      double best_d = HUGE_VAL;
      for (std::size_t n = 0; n < s.nodes.size(); ++n) {
        const double d = norm(s.nodes[n] - s.nodes[e]) / vs;
        if (d > reach || g[n] < 8 * cover || d >= best_d) continue;
        // The gap goes through the solid (95% of its samples).
        int in = 0, all = 0;
        for (double t = 0; t <= 1; t += 0.25 / std::max(d, 1.0), ++all) in += inside(s.nodes[e] + (s.nodes[n] - s.nodes[e]) * t);
        if (in < 0.95 * all) continue;
        std::vector<Vec3> loop;
        for (std::int64_t m = std::int64_t(n); m >= 0; m = back[std::size_t(m)]) loop.push_back(s.nodes[std::size_t(m)]);
        if (around_a_hole(loop)) best = n, best_d = d;
      }
      if (best != e) gaps.push_back({Index(e), Index(best), best_d});
      continue;
    }
    std::size_t best = e;
    double best_d = HUGE_VAL;
    bool best_is_end = false;  // another end is preferred: the two close the loop cleanly

    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      const double d = norm(s.nodes[n] - s.nodes[e]) / vs;
      const bool is_end = degree[n] == 1;
      if (d > reach || g[n] < 4 * reach || (best_is_end && !is_end) || (is_end == best_is_end && d >= best_d)) continue;
      // The straight way must stay in voted voxels (votes are sparse: 90%
      // of its samples).
      int in = 0, all = 0;
      for (double t = 0; t <= 1; t += 0.25 / std::max(d, 1.0), ++all) {
        const VoxelIndex c = votes.locate(s.nodes[e] + (s.nodes[n] - s.nodes[e]) * t);
        in += votes.contains(c) && mask[votes.linear(c)];
      }
      if (in >= 0.9 * all) best = n, best_d = d, best_is_end = is_end;
    }
    if (best == e) continue;
    close_gap(Index(e), Index(best), reach);
  }
  if (tunnels) {
    std::sort(gaps.begin(), gaps.end(), [](const Gap& a, const Gap& b) { return a.d < b.d; });
    for (const Gap& c : gaps)
      if (int(closing.size()) < max_loops && !closed[c.e]) close_gap(c.e, c.n, 2 * (1.5 * thick[voxel_of[c.e]] + 2));
  }
  // Each loop is closed along the ridge of votes: the intensity-driven
  // shortest path between the two voxels, through voted voxels.
  std::fill(cost.begin(), cost.end(), HUGE_VAL);
  for (const auto& c : closing) {
    const std::size_t from = voxel_of[c[0]], to = voxel_of[c[1]];
    std::vector<std::size_t> touched;
    using Item = std::pair<double, std::size_t>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
    cost[from] = 0;
    parent[from] = -1;
    touched.push_back(from);
    q.push({0, from});
    bool reached = false;
    while (!q.empty()) {
      const auto [cn, n] = q.top();
      q.pop();
      if (cn > cost[n]) continue;
      if (n == to) {
        reached = true;
        break;
      }
      for (std::size_t k = 0; k < 26; ++k) {
        const std::size_t m = std::size_t(std::ptrdiff_t(n) + offset[k]);
        if (!mask[m]) continue;
        const double nc = cn + step[k].length / r2(m);
        if (nc < cost[m]) {
          if (cost[m] == HUGE_VAL) touched.push_back(m);
          cost[m] = nc;
          parent[m] = std::int32_t(n);
          q.push({nc, m});
        }
      }
    }
    if (reached) {
      const auto link = [&](Index a, Index b) {
        const bool twice = a == b || std::any_of(s.edges.begin(), s.edges.end(), [&](const std::array<Index, 2>& x) {
                             return (x[0] == a && x[1] == b) || (x[0] == b && x[1] == a);
                           });
        if (!twice) s.edges.push_back({a, b});
      };
      Index prev = c[1];
      for (std::int64_t n = parent[to]; n >= 0 && std::size_t(n) != from; n = parent[std::size_t(n)]) {
        const Index cur = node(std::size_t(n));
        link(prev, cur);
        prev = cur;
      }
      link(prev, c[0]);
    }
    for (std::size_t n : touched) cost[n] = HUGE_VAL;
  }
  // The closing path may run into a branch short of its end, which is left
  // as a spur: terminal branches shorter than min_branch go.
  if (!closing.empty())
    prune_spurs(s, [&](const std::vector<Index>&, double length, Index tip) {
      // A spur that ends where a loop was closed is what remains of the
      // other side of the gap.
      const bool gap_side = tip < closed.size() && closed[tip];
      return length < min_branch * vs || gap_side;
    });
  return s;
}

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
  if (merge_length > 0) prune_spurs(s, [&](const std::vector<Index>&, double length, Index) { return length < merge_length; });
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

ProjectionResult skeleton_from_projections(render::Renderer& renderer, const Mesh& mesh, const ProjectionParams& p,
                                           const Context* ctx) {
  p.check();
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: it has no silhouette");
  BBox box;
  for (const Vec3& v : mesh.positions) box.add(v);
  ProjectionResult out;
  auto t = std::chrono::steady_clock::now();
  if (ctx) ctx->progress(0.0, "rendering silhouettes");
  std::vector<render::CameraMatrices> cameras;
  for (const Vec3& d : render::sphere_directions(p.views / 2)) {
    cameras.push_back(render::orthographic_view(d, box, p.image, p.image));
    cameras.push_back(render::orthographic_view(d * -1.0, box, p.image, p.image));
  }
  const std::vector<render::ViewCapture> views = render::capture_cameras(renderer, mesh, cameras, p.contexts);
  out.render_seconds = seconds_since(t);
  if (ctx) {
    ctx->check_cancelled();
    ctx->progress(0.4, "medial axes and votes");
  }
  {
    const render::ViewCapture& v = views[0];
    const std::vector<std::uint8_t> axis = medial_axis(chamfer_34(v.silhouette, p.image, p.image), p.image, p.image, p.min_radius);
    out.first_view.resize(axis.size());
    for (std::size_t i = 0; i < axis.size(); ++i) out.first_view[i] = axis[i] ? 2 : v.silhouette[i];
  }
  t = std::chrono::steady_clock::now();
  std::vector<float> radius;
  out.votes = vote(views, box, p, &radius, ctx);
  out.vote_seconds = seconds_since(t);
  if (ctx) ctx->progress(0.8, "thinning");
  t = std::chrono::steady_clock::now();
  // The loops the skeleton may have: the genus of a closed, oriented mesh
  // (its tunnels), found through the solid; other meshes: as the votes say.
  const MeshReport report = mesh_report(mesh);
  out.genus = report.closed && report.oriented && report.genus ? int(*report.genus) : -1;
  const RayCaster caster(mesh);
  out.skeleton = thin(out.votes, radius, p, out.genus, [&](const Vec3& q) { return caster.inside(q); });
  // Smoothing may not move a node out of the mesh.
  simplify(out.skeleton, p.merge_distance * box.diagonal(), p.smoothing,
           [&](const Vec3& q) { return caster.inside(q); });
  // A node the votes put outside (a thin part, seen thicker than it is from
  // some views) moves towards a neighbour that is inside until it is too.
  Skeleton& s = out.skeleton;
  const Adjacency adj = skeleton_adjacency(s);
  std::vector<std::uint8_t> in(s.nodes.size());
  for (std::size_t n = 0; n < s.nodes.size(); ++n) in[n] = caster.inside(s.nodes[n]);
  for (int pass = 0; pass < 8; ++pass)
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      if (in[n]) continue;
      for (const std::uint32_t* m = adj.begin(n); m != adj.end(n) && !in[n]; ++m) {
        if (!in[*m]) continue;
        Vec3 q = s.nodes[n];
        for (int k = 0; k < 12 && !in[n]; ++k) {
          q = (q + s.nodes[*m]) * 0.5;
          if (caster.inside(q)) s.nodes[n] = q, in[n] = 1;
        }
      }
    }
  out.thin_seconds = seconds_since(t);
  return out;
}

}  // namespace cgview::skeleton
