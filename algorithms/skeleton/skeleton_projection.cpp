#include "skeleton/skeleton_projection.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <functional>
#include <memory>
#include <future>
#include <optional>
#include <cmath>
#include <ctime>
#include <numeric>
#include <queue>
#include <tuple>
#include <unordered_map>
#include <thread>

#include "core/cluster_decimate.h"
#include "core/threads.h"
#include "core/union_find.h"
#include "core/mesh_report.h"
#include "rays/ray_caster.h"
#include "voxel/voxelize.h"
#include "registry/registry.h"
#include "render/renderer.h"
#include "render/views.h"

namespace cgview::skeleton {
namespace {

// A stage's wall and process CPU seconds (all threads: the views and the
// votes use several).
struct Stopwatch {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  std::clock_t cpu = std::clock();
  // The time since the start (or the last stop), and starts again.
  void stop(double& wall_seconds, double& cpu_seconds) {
    const auto w = std::chrono::steady_clock::now();
    const std::clock_t c = std::clock();
    wall_seconds = std::chrono::duration<double>(w - wall).count();
    cpu_seconds = double(c - cpu) / CLOCKS_PER_SEC;
    wall = w;
    cpu = c;
  }
};

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

// The vote grid's voxel: `grid` of them along the box's longest side.
double vote_voxel_size(const BBox& box, const ProjectionParams& p) {
  const Vec3 size = box.size();
  return std::max({size.x, size.y, size.z, 1e-12}) / p.grid;
}

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
  need(render_faces >= 0, "parameter 'render_faces' must be >= 0");
}

std::vector<std::uint16_t> chamfer_34(const std::vector<std::uint8_t>& mask, int w, int h) {
  constexpr std::uint16_t far = 60000;
  // On a copy with one pixel of outside around it, so that no neighbour
  // needs a bounds check.
  const int pw = w + 2;
  std::vector<std::uint16_t> d(std::size_t(pw) * (h + 2), 0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* m = &mask[std::size_t(y) * w];
    std::uint16_t* row = &d[std::size_t(y + 1) * pw + 1];
    for (int x = 0; x < w; ++x) row[x] = m[x] ? far : 0;
  }
  for (int y = 1; y <= h; ++y) {
    std::uint16_t* r = &d[std::size_t(y) * pw];
    const std::uint16_t* up = r - pw;
    for (int x = 1; x <= w; ++x)
      if (r[x]) r[x] = std::uint16_t(std::min({int(r[x]), r[x - 1] + 3, up[x] + 3, up[x - 1] + 4, up[x + 1] + 4}));
  }
  for (int y = h; y >= 1; --y) {
    std::uint16_t* r = &d[std::size_t(y) * pw];
    const std::uint16_t* down = r + pw;
    for (int x = w; x >= 1; --x)
      if (r[x])
        r[x] = std::uint16_t(std::min({int(r[x]), r[x + 1] + 3, down[x] + 3, down[x + 1] + 4, down[x - 1] + 4}));
  }
  std::vector<std::uint16_t> out(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) std::copy_n(&d[std::size_t(y + 1) * pw + 1], w, &out[std::size_t(y) * w]);
  return out;
}

std::vector<std::uint8_t> medial_axis(const std::vector<std::uint16_t>& dt, int w, int h, int min_radius) {
  std::vector<std::uint8_t> axis(dt.size(), 0);
  const int least = std::max(1, 3 * min_radius);
  const auto at = [&](int x, int y) -> int {
    return x < 0 || y < 0 || x >= w || y >= h ? 0 : dt[std::size_t(y) * w + x];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int v = dt[std::size_t(y) * w + x];
      if (v < least) continue;
      // A neighbour off the image is outside (0), never a bigger disc.
      axis[std::size_t(y) * w + x] = at(x - 1, y) < v + 3 && at(x + 1, y) < v + 3 && at(x, y - 1) < v + 3 &&
                                     at(x, y + 1) < v + 3 && at(x - 1, y - 1) < v + 4 && at(x + 1, y - 1) < v + 4 &&
                                     at(x - 1, y + 1) < v + 4 && at(x + 1, y + 1) < v + 4;
    }
  return axis;
}

Votes vote(const std::vector<render::ViewCapture>& views, const BBox& box, const ProjectionParams& p,
           const Context* ctx) {
  for (const render::ViewCapture& v : views)
    if (v.back_depth.size() != v.depth.size()) throw InvalidInput("vote: every view needs its back depth");
  const Vec3 size = box.size();
  const double vs = vote_voxel_size(box, p);
  const std::array<int, 3> dims{int(std::ceil(size.x / vs)) + 2, int(std::ceil(size.y / vs)) + 2,
                                int(std::ceil(size.z / vs)) + 2};
  const Vec3 origin = box.min - Vec3{vs, vs, vs};
  VoxelGrid grid(dims, origin, vs, VoxelType::float32);
  const int threads = std::max(1, std::min<int>(int(std::thread::hardware_concurrency()), int(views.size())));
  // Each thread votes into a grid of its own, a voxel's votes beside the
  // sum of their radii (a ray's samples are far apart in memory: one cache
  // line for both), added after.
  std::vector<std::vector<std::array<float, 2>>> partial(threads);
  auto work = [&](int t) {
    std::vector<std::array<float, 2>>& acc = partial[t];
    acc.assign(grid.size(), {0.f, 0.f});
    for (std::size_t v = std::size_t(t); v < views.size(); v += std::size_t(threads)) {
      if (t == 0 && ctx && ctx->cancelled()) return;
      const render::ViewCapture& view = views[v];
      const int w = view.camera.width, h = view.camera.height;
      const std::vector<std::uint16_t> dt = chamfer_34(view.silhouette, w, h);
      const std::vector<std::uint8_t> axis = medial_axis(dt, w, h, p.min_radius);
      const Vec3 dir = view.camera.forward();
      const double pixel = view.camera.pixel_size_at(0);
      // The camera's matrix inverted once per view (unproject would invert it
      // at every pixel).
      const render::Mat4 from_view = render::inverse(view.camera.view_projection());
      const auto unproject = [&](double x, double y, float depth) {
        return render::transform_point(from_view, Vec3{2 * x / w - 1, 1 - 2 * y / h, 2 * double(depth) - 1});
      };
      // The ray's samples, every half voxel, in voxel units from the grid's origin.
      const Vec3 half_step = dir * 0.5;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t i = std::size_t(y) * w + x;
          if (!axis[i] || view.depth[i] >= 1.f) continue;
          const Vec3 entry = unproject(x + 0.5, y + 0.5, view.depth[i]);
          const Vec3 exit = unproject(x + 0.5, y + 0.5, view.back_depth[i]);
          const double radius_world = dt[i] / 3.0 * pixel;
          const double length = std::min(2 * radius_world, std::max(0.0, dot(exit - entry, dir)));
          const int samples = int(std::floor(length / (vs / 2))) + 1;
          // The ray votes from where it enters, and (as the antipodal view's
          // ray) back from where it leaves: where it crosses the shape twice,
          // both parts it crosses.
          for (const auto& [from, step] : {std::pair{entry, half_step}, std::pair{exit, half_step * -1.0}}) {
            // A straight ray leaves a voxel for good: a sample in the voxel of
            // the one before is the same vote.
            std::size_t last = SIZE_MAX;
            Vec3 g = (from - origin) / vs;
            for (int k = 0; k < samples; ++k, g += step) {
              const double fx = std::floor(g.x), fy = std::floor(g.y), fz = std::floor(g.z);
              if (!(fx >= 0 && fy >= 0 && fz >= 0 && fx < dims[0] && fy < dims[1] && fz < dims[2])) continue;
              const std::size_t n =
                  std::size_t(fx) + std::size_t(dims[0]) * (std::size_t(fy) + std::size_t(dims[1]) * std::size_t(fz));
              if (n == last) continue;
              last = n;
              acc[n][0] += 1.f;
              acc[n][1] += float(radius_world);
            }
          }
        }
    }
  };
  on_threads(threads, work);
  if (ctx) ctx->check_cancelled();
  // The threads' grids added up, a range of voxels each.
  std::vector<float>& out = grid.floats();
  std::vector<float> radius(grid.size(), 0.f);
  on_threads(threads, [&](int t) {
    const std::size_t a = grid.size() * std::size_t(t) / std::size_t(threads);
    const std::size_t b = grid.size() * std::size_t(t + 1) / std::size_t(threads);
    for (std::size_t n = a; n < b; ++n) {
      float v = 0, r = 0;
      for (const auto& part : partial) v += part[n][0], r += part[n][1];
      out[n] = v;
      radius[n] = v > 0 ? r / v : 0.f;
    }
  });
  return {std::move(grid), std::move(radius)};
}

Skeleton thin(const VoxelGrid& votes, const std::vector<float>& radius, const ProjectionParams& p, int max_loops,
              const std::function<bool(const Vec3&)>& inside) {
  const Lattice L{votes.dims()};
  const std::vector<float>& I = votes.floats();
  const float top = I.empty() ? 0.f : *std::max_element(I.begin(), I.end());
  Skeleton s;
  if (!(top > 0)) return s;
  // The domain, numbered (the arrays below are over it): the voxels with at
  // least a fifth of the targets' votes (5% of the most, by default: half
  // the voted voxels on the elephant, and the weakly voted rim that no
  // path of the skeleton takes), unless that splits the targets into
  // several components: then every voted voxel (the inside, as far as the
  // views tell).  The targets: the voxels voted enough, which branches must
  // reach.  The domain leaves the grid's border out (votes fall inside the
  // bounding box, a voxel in from the border), so that the paths below step
  // by linear offsets.
  const double least_target = p.threshold * top;
  std::vector<std::int32_t> id(L.size(), -1);  // a voxel's number in the domain (grids up to 512³ fit 32 bits)
  std::vector<std::size_t> vox;                // a number's voxel
  const std::vector<std::ptrdiff_t> offset = L.offsets();
  const std::vector<Step>& step = steps26();
  // The domain's 26-neighbours of a numbered voxel: f(number, step k); from
  // step 13 on, only those ahead in the scan order (numbered after it: each
  // pair once; steps26 goes k from -1 to 1).  Looked up in the grid's
  // numbering each time: the walks below visit about half the domain once,
  // so a table of all of them would cost more than it saves.
  const auto neighbours = [&](std::size_t c, auto&& f, std::size_t first = 0) {
    const std::int32_t* here = &id[vox[c]];
    for (std::size_t k = first; k < 26; ++k)
      if (const std::int32_t m = here[offset[k]]; m >= 0) f(std::size_t(m), k);
  };
  constexpr std::size_t ahead = 13;
  // The components (union-find over the neighbours ahead; each joined to its
  // lowest number).
  UnionFind sets;
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
  const std::size_t count = vox.size();
  std::vector<std::uint8_t> target(count);
  // The intensity weight of a step onto a voxel.
  std::vector<double> r2(count);
  // The local radius of the shape, in voxels: the mean radius of the medial
  // discs that voted for the voxel (the vote set itself is thinner).
  std::vector<float> thick(count, 1.f);
  const double vs = votes.voxel_size();
  for (std::size_t c = 0; c < count; ++c) {
    const float v = I[vox[c]];
    target[c] = v >= least_target;
    const double r = v / top + 0.01;
    r2[c] = r * r;
    if (!radius.empty()) thick[c] = float(radius[vox[c]] / vs);
  }
  std::vector<std::uint32_t> targets_of(count, 0);  // of a component, at its lowest number
  for (std::size_t c = 0; c < count; ++c) targets_of[sets.find(std::uint32_t(c))] += target[c];
  const Vec3 ext = Vec3{double(L.d[0]), double(L.d[1]), double(L.d[2])} * vs;
  const double diagonal = norm(ext);
  const double min_branch = p.min_branch * diagonal / vs;  // in voxels

  std::vector<std::int32_t> node_of(count, -1);  // skeleton node of a numbered voxel
  // A node sits at the vote-weighted centre of its voxel's 3x3x3
  // neighbourhood: off the voxel lattice, towards the ridge of votes.
  const auto node = [&](std::size_t c) {
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
  };
  std::vector<std::uint8_t> done(count, 0);  // voxels of components already processed
  std::vector<double> cost(count, HUGE_VAL), along(count, 0);
  std::vector<std::int32_t> parent(count, -1);
  // The voxels a branch covers: those within 1.5 x the local radius + 2
  // (in voxels, rounded up) of its voxels, kept as the balls (centre,
  // squared radius); only targets are ever asked about.
  std::vector<std::array<int, 4>> balls;
  std::vector<std::uint8_t> reached(count, 0);  // targets that started a branch
  const auto covered = [&](std::size_t c) {
    if (reached[c]) return true;
    const auto [i, j, k] = L.ijk(vox[c]);
    return std::any_of(balls.rbegin(), balls.rend(), [&, i = i, j = j, k = k](const std::array<int, 4>& b) {
      return (i - b[0]) * (i - b[0]) + (j - b[1]) * (j - b[1]) + (k - b[2]) * (k - b[2]) <= b[3];
    });
  };

  const bool tunnels = inside && max_loops >= 0;  // a closed mesh: its loops are its tunnels, at most its genus
  // Components in order of their most voted voxel.
  std::vector<std::size_t> order;
  for (std::size_t c = 0; c < count; ++c)
    if (target[c]) order.push_back(c);
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
    while (!q.empty() && (members.size() < targets || (tunnels && max_loops > 0))) {
      const auto [c, n] = q.pop();
      if (c > cost[n] || done[n]) continue;
      done[n] = 1;
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
      const bool keep =
          along[far] - along[join] >= min_branch && (main_votes < 0 || mean >= p.branch_votes * main_votes);
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
  if (s.edges.empty()) return s;

  // Loops.  The skeleton so far is a tree; a loop closes where the shape
  // has a tunnel.
  std::vector<std::size_t> voxel_of(s.nodes.size());  // a node's numbered voxel
  for (std::size_t c = 0; c < count; ++c)
    if (node_of[c] >= 0) voxel_of[std::size_t(node_of[c])] = c;
  const std::vector<std::uint32_t> degree = node_degrees(s);  // the tree's
  const std::size_t tree_edges = s.edges.size();
  std::vector<std::uint8_t> closed(s.nodes.size(), 0);  // the tree's ends beside a loop's closing
  // How far a branch through a voxel covers, in voxels.
  const auto cover = [&](std::size_t c) { return 1.5 * thick[c] + 2; };
  // Distances along the skeleton from `from` (Dijkstra over its edges, in
  // voxels), with the way back.
  std::vector<double> g;
  std::vector<std::int32_t> back;
  Adjacency adj;
  std::size_t adj_edges = 0;  // the edges adj was made from
  const auto along_skeleton = [&](Index from) {
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
  };
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
  if (tunnels && max_loops > 0) {
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
    for (std::size_t k : best) {
      if (loops >= max_loops) break;
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
  } else if (!tunnels) {
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
      if (degree[e] != 1 || taken[e]) continue;
      const double reach = 2 * cover(voxel_of[e]);
      along_skeleton(Index(e));
      std::size_t best = e;
      double best_d = HUGE_VAL;
      bool best_is_end = false;
      for (std::size_t n = 0; n < degree.size(); ++n) {
        const double d = norm(s.nodes[n] - s.nodes[e]) / vs;
        const bool is_end = degree[n] == 1;
        if (d > reach || g[n] < 4 * reach || (best_is_end && !is_end) || (is_end == best_is_end && d >= best_d))
          continue;
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
    for (const Gap& x : gaps) {
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
  // The closing path may run into a branch short of its end, which is left
  // as a spur: terminal branches shorter than min_branch go.
  if (s.edges.size() > tree_edges)
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

ProjectionResult skeleton_from_projections(render::Renderer& renderer, const Mesh& mesh, const ProjectionParams& p,
                                           const Context* ctx) {
  p.check();
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: it has no silhouette");
  const BBox box = bounding_box(mesh);
  ProjectionResult out;
  Stopwatch watch;
  if (ctx) ctx->progress(0.0, "rendering silhouettes");
  // One drawing per antipodal pair: an orthographic view's back depth is its
  // antipode's depth, and its silhouette the antipode's mirrored.
  std::vector<render::CameraMatrices> cameras;
  for (const Vec3& d : render::sphere_directions(p.views / 2))
    cameras.push_back(render::orthographic_view(d, box, p.image, p.image));
  // The silhouettes of a big mesh from a decimated copy (the bounding box,
  // the cameras and the inside tests stay the full mesh's).
  Mesh decimated;
  if (p.render_faces > 0 && mesh.faces.size() > std::size_t(p.render_faces))
    decimated = cluster_decimate(mesh, {std::size_t(p.render_faces)}).mesh;
  const Mesh& drawn = decimated.faces.empty() ? mesh : decimated;
  out.faces_drawn = drawn.faces.size();
  // What needs the mesh alone, on a thread of its own while the views are
  // drawn: its report (whether it is closed, its genus), its ray caster (the
  // inside tests) and, for a closed mesh, its solid at the votes' voxel size
  // (the drawn copy: the surface's voxels and those it encloses).
  struct Solid {
    MeshReport report;
    std::unique_ptr<RayCaster> caster;
    std::optional<VoxelGrid> grid;
  };
  // Its context passes cancellation on, not progress: the job's progress
  // is this thread's.
  const Context solid_ctx(nullptr, [ctx] { return ctx && ctx->cancelled(); });
  std::future<Solid> solid_future = std::async(std::launch::async, [&] {
    Solid solid{mesh_report(mesh), std::make_unique<RayCaster>(mesh), std::nullopt};
    if (solid.report.closed) {
      VoxelizeParams vp;
      vp.voxel_size = vote_voxel_size(box, p);
      vp.box = box;  // the votes' grid, voxel for voxel (a decimated copy's own box is smaller)
      vp.threads = 1;
      solid.grid = voxelize(drawn, vp, &solid_ctx).grid;
    }
    return solid;
  });
  const std::vector<render::ViewCapture> views =
      render::capture_cameras(renderer, drawn, cameras, p.contexts, {.back_depth = true});
  watch.stop(out.render_seconds, out.render_cpu_seconds);
  if (ctx) {
    ctx->check_cancelled();
    ctx->progress(0.4, "medial axes and votes");
  }
  {
    const render::ViewCapture& v = views[0];
    const std::vector<std::uint8_t> axis =
        medial_axis(chamfer_34(v.silhouette, p.image, p.image), p.image, p.image, p.min_radius);
    out.first_view.resize(axis.size());
    for (std::size_t i = 0; i < axis.size(); ++i) out.first_view[i] = axis[i] ? 2 : v.silhouette[i];
  }
  watch = Stopwatch{};  // restarted: the first view's medial axis (an artifact) is not a stage
  Votes votes = vote(views, box, p, ctx);
  out.votes = std::move(votes.grid);
  const std::vector<float>& radius = votes.radius;
  const Solid solid = solid_future.get();
  // The loops the skeleton may have: the genus of a closed, oriented mesh
  // (its tunnels), found through the solid; other meshes: as the votes say.
  const MeshReport& report = solid.report;
  out.genus = report.closed && report.oriented && report.genus ? int(*report.genus) : -1;
  // A ray knows only where it enters the shape and where it leaves it, so
  // it votes across whatever lies between (the hole of a ring seen edge-on,
  // the gap between two arms): a closed mesh's votes are kept to its solid.
  if (solid.grid) {
    const VoxelGrid& g = *solid.grid;
    std::vector<float>& v = out.votes.floats();
    for (std::size_t n = 0; n < v.size(); ++n)
      if (v[n] > 0) {
        const VoxelIndex at = g.locate(out.votes.center(out.votes.unlinear(n)));
        if (!g.contains(at) || !g.bytes()[g.linear(at)]) v[n] = 0;
      }
  }
  watch.stop(out.vote_seconds, out.vote_cpu_seconds);
  if (ctx) ctx->progress(0.8, "thinning");
  const RayCaster& caster = *solid.caster;
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
  watch.stop(out.thin_seconds, out.thin_cpu_seconds);
  return out;
}

}  // namespace cgview::skeleton
