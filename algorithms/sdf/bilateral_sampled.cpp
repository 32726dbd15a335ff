#include "sdf/bilateral_sampled.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <type_traits>
#include <utility>

#include "core/threads.h"
#include "sdf/bilateral_filter.h"
#include "sdf/bilateral_sums.h"
#include "sdf/curve_order.h"
#include "sdf/parallel_blocks.h"

namespace cgview::sdf {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr int kMostNear = 24;                 // sites interpolated per face, at most
constexpr std::size_t kSetUpBlock = 1 << 16;  // faces a block in the set-up's parallel passes

// Sites: each face in turn (along the curve, so that they spread
// evenly), unless one is within `spacing` rings already; each face's
// nearest site (by rings) is the one that last lowered its ring.
// Each site's neighbours: the sites whose regions touch its own
// (kMostNear - 1 of them at most).
struct Regions {
  std::vector<std::uint32_t> sites;
  std::vector<std::uint32_t> site_of;
  std::vector<std::uint32_t> near;       // kMostNear - 1 per site
  std::vector<std::uint8_t> near_count;  // per site
  std::span<const std::uint32_t> near_of(std::size_t k) const {
    return {near.data() + k * (kMostNear - 1), near_count[k]};
  }
};

template <class Graph>
Regions regions_of(const Graph& g, int spacing) {
  Regions r;
  std::vector<std::uint8_t> ring(g.size(), std::numeric_limits<std::uint8_t>::max());
  r.site_of.assign(g.size(), kNone);
  std::vector<std::uint32_t> queue;
  for (std::size_t s = 0; s < g.size(); ++s) {
    if (ring[s] <= spacing) continue;
    const std::uint32_t k = std::uint32_t(r.sites.size());
    r.sites.push_back(std::uint32_t(s));
    ring[s] = 0, r.site_of[s] = k;
    queue.assign(1, std::uint32_t(s));
    // Rings only fall: a walk stops where they are no lower.
    for (std::size_t q = 0; q < queue.size(); ++q)
      if (ring[queue[q]] < spacing)
        for (const std::uint32_t* h = g.begin(queue[q]); h != g.end(queue[q]); ++h)
          if (ring[*h] > ring[queue[q]] + 1)
            ring[*h] = std::uint8_t(ring[queue[q]] + 1), r.site_of[*h] = k, queue.push_back(*h);
  }
  const std::vector<std::uint32_t>& sites = r.sites;
  r.near.resize(sites.size() * (kMostNear - 1));
  r.near_count.assign(sites.size(), 0);
  // On every core, a lock per site (two threads meet at a site only where
  // their blocks of faces do); each list sorted afterwards, and where a
  // site has more neighbours than fit, the lowest numbered kept, so that
  // the lists do not depend on the threads' timing.
  std::vector<std::atomic_flag> lock(sites.size());
  parallel_blocks(g.size(), kSetUpBlock / 4, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    std::uint32_t last_s = kNone, last_t = kNone;
    for (std::size_t f = b; f < e; ++f) {
      const std::uint32_t s = r.site_of[f];
      for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) {
        const std::uint32_t t = r.site_of[*h];
        if (t == s || (s == last_s && t == last_t)) continue;
        last_s = s, last_t = t;
        while (lock[s].test_and_set(std::memory_order_acquire)) {
        }
        std::uint32_t* near = r.near.data() + s * (kMostNear - 1);
        std::uint32_t* end = near + r.near_count[s];
        if (std::find(near, end, t) == end) {
          if (r.near_count[s] < kMostNear - 1) *end = t, ++r.near_count[s];
          else if (std::uint32_t* most = std::max_element(near, end); t < *most) *most = t;
        }
        lock[s].clear(std::memory_order_release);
      }
    }
  });
  parallel_blocks(sites.size(), kSetUpBlock / 4, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      std::uint32_t* near = r.near.data() + k * (kMostNear - 1);
      std::sort(near, near + r.near_count[k]);
    }
  });
  return r;
}

// The value at d = 0 of the least-squares plane through (d_j, v_j) with
// weights w_j, and the plane's slope; false where the sites do not span a
// plane around the face.  The slope's components along the surface normal
// are damped (the sites lie on the surface, a plane through them is
// undetermined across it).
bool fit_plane(int m, const Vec3* d, const double* v, const double* w, double& value, Vec3& slope) {
  // The normal equations (symmetric, positive definite once damped),
  // solved by Cholesky.
  double a[4][4] = {}, rhs[4] = {};
  double scale = 0;
  for (int j = 0; j < m; ++j) {
    const double e[4] = {1, d[j].x, d[j].y, d[j].z};
    for (int r = 0; r < 4; ++r) {
      const double we = w[j] * e[r];
      for (int c = 0; c <= r; ++c) a[r][c] += we * e[c];
      rhs[r] += we * v[j];
    }
    scale += w[j] * dot(d[j], d[j]);
  }
  if (!(scale > 0)) return false;
  for (int r = 1; r < 4; ++r) a[r][r] += 1e-3 * scale;
  for (int c = 0; c < 4; ++c) {
    double pivot = a[c][c];
    for (int k = 0; k < c; ++k) pivot -= a[c][k] * a[c][k];
    if (!(pivot > 0)) return false;
    a[c][c] = std::sqrt(pivot);
    for (int r = c + 1; r < 4; ++r) {
      double x = a[r][c];
      for (int k = 0; k < c; ++k) x -= a[r][k] * a[c][k];
      a[r][c] = x / a[c][c];
    }
  }
  double y[4], x[4];
  for (int r = 0; r < 4; ++r) {
    y[r] = rhs[r];
    for (int k = 0; k < r; ++k) y[r] -= a[r][k] * y[k];
    y[r] /= a[r][r];
  }
  for (int r = 3; r >= 0; --r) {
    x[r] = y[r];
    for (int k = r + 1; k < 4; ++k) x[r] -= a[k][r] * x[k];
    x[r] /= a[r][r];
  }
  value = x[0], slope = {x[1], x[2], x[3]};
  return std::isfinite(value);
}

// A face's neighbours (three at most) and value, for the walks.
struct FaceRecord {
  std::uint32_t near[3];
  float value;
};

// Records as a graph: a face with fewer than three neighbours has itself
// in their place (no walk goes anywhere by it).
struct RecordGraph {
  const FaceRecord* record;
  std::size_t n;
  std::size_t size() const { return n; }
  const std::uint32_t* begin(std::size_t f) const { return record[f].near; }
  const std::uint32_t* end(std::size_t f) const { return record[f].near + 3; }
};

// Values to bins: round((x - lo) / step).
struct Binning {
  float lo, inverse_step;
  int bins;
  const std::uint16_t* of = nullptr;  // each face's bin, as below (none where NaN)
  int operator()(float x) const { return std::min(int((x - lo) * inverse_step + 0.5f), bins - 1); }
};

// One window, exact: the faces within `window` rings of a face, breadth
// first, binned by value (each bin its spatial weight and weighted sum of
// values), with the count, sum and sum of squares of the values.
class WindowWalk {
 public:
  // The bins of the last window run as their means and their weights
  // relative to the heaviest (a factor a bin rather than a logarithm: a
  // scalar logarithm a bin took about 2% of the time); the bins zero again.
  // False where the window has no value.
  bool summarize() {
    mean_.clear(), weight_.clear();
    if (count_ == 0) return false;
    float heaviest = 0;
    for (const Bin& b : bin_) heaviest = std::max(heaviest, b.weight);
    const float inverse = 1 / heaviest;
    for (Bin& b : bin_) {
      if (b.weight > 0) mean_.push_back(b.moment / b.weight), weight_.push_back(b.weight * inverse);
      b = {};
    }
    return true;
  }

  // The filtered value of a face with value c and this window (summarized).
  double at(double c, double step) const {
    const double dev2 = (squares_ - 2 * c * sum_ + double(count_) * c * c) / double(count_);
    if (!(dev2 > 1e-12 * step * step)) return c;
    float s = 0, w = 0;
    scaled_weighted_sums(mean_.data(), weight_.data(), mean_.size(), float(c), float(0.5 / (2.25 * dev2)), s, w);
    return s / w;
  }

  // Faces as records or a graph (no face with more than `degree`
  // neighbours) and values.
  void run(const RecordGraph& g, std::uint32_t start, const std::vector<float>& ring_weight, const Binning& binning) {
    const FaceRecord* record = g.record;
    const std::size_t n = g.n;
    walk(
        n, 3, start, ring_weight, binning, [record](std::uint32_t f) { return record[f].value; },
        [record](std::uint32_t f, std::uint32_t* tail, std::size_t& size, std::uint8_t* seen, std::uint8_t mark) {
          const FaceRecord& r = record[f];
          for (int j = 0; j < 3; ++j) {
            const std::uint32_t m = r.near[j];
            const bool fresh = seen[m] != mark;
            seen[m] = mark;
            tail[size] = m;
            size += fresh;
          }
        });
  }
  void run(const Adjacency& g, std::size_t degree, const float* value, std::uint32_t start,
           const std::vector<float>& ring_weight, const Binning& binning) {
    walk(
        g.size(), degree, start, ring_weight, binning, [value](std::uint32_t f) { return value[f]; },
        [&g](std::uint32_t f, std::uint32_t* tail, std::size_t& size, std::uint8_t* seen, std::uint8_t mark) {
          for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) {
            const std::uint32_t m = *h;
            const bool fresh = seen[m] != mark;
            seen[m] = mark;
            tail[size] = m;
            size += fresh;
          }
        });
  }

 private:
  std::vector<std::uint32_t> queue_;
  std::vector<std::uint8_t> seen_;  // the walk's mark where met
  std::uint8_t mark_ = 0;
  // A bin's spatial weight and weighted sum of values side by side: one
  // load and one store of both.
  struct alignas(8) Bin {
    float weight = 0, moment = 0;
  };
  std::vector<Bin> bin_;
  std::size_t count_ = 0;
  double sum_ = 0, squares_ = 0;
  std::vector<float> mean_, weight_;  // the bins used, as summarize leaves them

  template <class Value, class Expand>
  void walk(std::size_t n, std::size_t degree, std::uint32_t start, const std::vector<float>& ring_weight,
            const Binning& binning, const Value& value_of, const Expand& expand) {
    if (seen_.size() != n) seen_.assign(n, 0), mark_ = 0;
    // A new mark for each walk, the marks cleared once every 255 walks.
    if (++mark_ == 0) std::fill(seen_.begin(), seen_.end(), 0), mark_ = 1;
    const std::uint8_t mark = mark_;
    if (bin_.size() != std::size_t(binning.bins)) bin_.assign(std::size_t(binning.bins), Bin{});
    // Locals: the compiler need not reload them after each store.
    std::uint8_t* const seen = seen_.data();
    if (queue_.size() < 64) queue_.resize(64);
    std::uint32_t* queue = queue_.data();
    Bin* const bins = bin_.data();
    const Binning to_bin = binning;
    const int window = int(ring_weight.size()) - 1;
    // The sums in float about the first face's value (a window's values
    // are close), the count as those met less those without a value.
    const float origin = value_of(start) == value_of(start) ? value_of(start) : 0.0f;
    float s = 0, q = 0, s1 = 0, q1 = 0;
    std::size_t missing = 0;
    queue[0] = start;
    seen[start] = mark;
    std::size_t size = 1;
    // Ring by ring: queue[begin, end) is the ring's faces.  Branch-free: a
    // face met again is written and then overwritten (a branch on it would
    // be mispredicted about every other time).
    for (std::size_t begin = 0, ring = 0; begin < size; ++ring) {
      const std::size_t end = size;
      const float w = ring_weight[ring];
      const bool outer = ring == std::size_t(window);
      // Room for every neighbour of the ring (the queue grows with the
      // windows, never to the mesh's size).
      if (!outer && queue_.size() < size + (end - begin) * degree + 1)
        queue_.resize(2 * (size + (end - begin) * degree + 1)), queue = queue_.data();
      const auto visit = [&](std::uint32_t f, float& sum, float& squares) {
        const float x = value_of(f);
        if (x == x) {  // NaN: walked through, not averaged
          const int i = to_bin.of[f];
          const float y = x - origin;
          sum += y, squares += y * y;
          bins[i].weight += w, bins[i].moment += w * x;
        } else {
          ++missing;
        }
        if (!outer) expand(f, queue, size, seen, mark);
      };
      // Two faces a step, each into its own sums: one chain of additions
      // would take a face per addition's latency.
      std::size_t k = begin;
      for (; k + 1 < end; k += 2) visit(queue[k], s, q), visit(queue[k + 1], s1, q1);
      if (k < end) visit(queue[k], s, q);
      begin = end;
    }
    count_ = size - missing;
    s += s1, q += q1;
    sum_ = double(s) + double(count_) * origin;
    squares_ = double(q) + 2.0 * origin * double(s) + double(count_) * double(origin) * origin;
  }
};

// The filter in the order given (faces numbered along a space-filling
// curve: each window's faces then lie close together in memory), face f's
// result written to out[order[f]] (faces without a value, or without one
// in their window, left as they are); false where all values are equal
// (or NaN).
template <class Graph>
bool sampled_pass(const std::vector<Vec3>& centre, const Graph& g, const std::vector<double>& values, int window,
                  const Context* ctx, const SampledFilterParams& p, SampledFilterStats& st, const std::uint32_t* order,
                  double* out) {
  const std::size_t n = values.size();
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (double v : values)
    if (!std::isnan(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!(hi > lo)) return false;
  const int bins = std::clamp(p.bins, 2, 1 << 16);  // a face's bin in 16 bits
  const double step = (hi - lo) / (bins - 1);

  const Regions regions = regions_of(g, p.spacing);
  const std::vector<std::uint32_t>& sites = regions.sites;
  st.sites = sites.size();

  // The centres each site will be asked about: its faces' and its
  // neighbours' faces' values, as a range of grid nodes: each region's
  // own range, widened by its neighbours'.
  std::vector<int> own_first(sites.size(), bins), own_last(sites.size(), -1);
  for (std::size_t f = 0; f < n; ++f) {
    if (std::isnan(values[f])) continue;
    const int below = std::clamp(int((values[f] - lo) / step), 0, bins - 2);
    const std::uint32_t s = regions.site_of[f];
    own_first[s] = std::min(own_first[s], below), own_last[s] = std::max(own_last[s], below + 1);
  }
  std::vector<int> first_node = own_first, last_node = own_last;
  for (std::size_t s = 0; s < sites.size(); ++s)
    for (std::uint32_t k : regions.near_of(s))
      first_node[k] = std::min(first_node[k], own_first[s]), last_node[k] = std::max(last_node[k], own_last[s]);
  std::vector<std::size_t> table_at(sites.size() + 1, 0);
  for (std::size_t k = 0; k < sites.size(); ++k)
    table_at[k + 1] = table_at[k] + std::size_t(std::max(0, last_node[k] - first_node[k] + 1));

  // Each site's window, exact, and from it the filtered value of a face
  // centred on the site with each value of its range of nodes.
  const double spatial = window / 2.0;
  std::vector<float> ring_weight(std::size_t(window) + 1);
  for (int l = 0; l <= window; ++l) ring_weight[std::size_t(l)] = float(std::exp(-0.5 * (l / spatial) * (l / spatial)));
  // Where the faces are not records (some face has more than three
  // neighbours), their values in float for the walks.
  constexpr bool kRecords = std::is_same_v<Graph, RecordGraph>;
  std::size_t degree = 0;
  std::vector<float> value32;
  if constexpr (!kRecords) {
    for (std::size_t f = 0; f < n; ++f) degree = std::max(degree, g.degree(f));
    value32.resize(n);
    for (std::size_t f = 0; f < n; ++f) value32[f] = float(values[f]);
  }
  const auto walk_from = [&](WindowWalk& walk, std::uint32_t f, const Binning& binning) {
    if constexpr (kRecords) walk.run(g, f, ring_weight, binning);
    else walk.run(g, degree, value32.data(), f, ring_weight, binning);
  };
  std::vector<float> table(table_at.back(), std::numeric_limits<float>::quiet_NaN());
  Binning binning{float(lo), float(1 / step), bins};
  // Each face's bin once, not at each of the walks that meet it (about 260
  // each on the 1.42M-face mesh): 0.90 -> 0.76 s there.
  std::vector<std::uint16_t> bin_of(n);
  parallel_blocks(n, kSetUpBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const float x = float(values[f]);
      bin_of[f] = x == x ? std::uint16_t(binning(x)) : 0;
    }
  });
  binning.of = bin_of.data();
  parallel_blocks(sites.size(), 16, thread_count(), ctx, 0.0, 0.6, "smoothing", [&](std::size_t b, std::size_t e) {
    thread_local WindowWalk walk;
    for (std::size_t k = b; k < e; ++k) {
      if (table_at[k + 1] == table_at[k]) continue;
      walk_from(walk, sites[k], binning);
      if (!walk.summarize()) continue;  // no value within the window
      for (int j = first_node[k]; j <= last_node[k]; ++j)
        table[table_at[k] + std::size_t(j - first_node[k])] = float(walk.at(lo + j * step, step));
      // The site itself from its own window at its own value.
      if (!std::isnan(values[sites[k]])) out[order[sites[k]]] = walk.at(values[sites[k]], step);
    }
  });

  // Each site's row of the table (indexed by node) and centre, in site
  // order: a face reads one entry of each for each of its sites.
  std::vector<const float*> row_of(sites.size());
  std::vector<Vec3> site_centre(sites.size());
  for (std::size_t k = 0; k < sites.size(); ++k)
    row_of[k] = table.data() + table_at[k] - first_node[k], site_centre[k] = centre[sites[k]];
  // Each face from its own site and that site's neighbours.
  // The tolerance is of the smoothed values' range (the sites' own), which
  // a few outlying raw values do not widen.
  double smooth_lo = HUGE_VAL, smooth_hi = -HUGE_VAL;
  for (std::size_t k = 0; k < sites.size(); ++k) {
    const double c = values[sites[k]];
    if (std::isnan(c)) continue;
    const double t = (c - lo) / step;
    const int below = std::clamp(int(t), 0, bins - 2);
    const float* row = &table[table_at[k]] - first_node[k];
    const double v = (1 - (t - below)) * row[below] + (t - below) * row[below + 1];
    if (!std::isnan(v)) smooth_lo = std::min(smooth_lo, v), smooth_hi = std::max(smooth_hi, v);
  }
  const double tolerance = p.tolerance * (smooth_hi > smooth_lo ? smooth_hi - smooth_lo : hi - lo);
  std::atomic<std::size_t> walked{0};
  parallel_blocks(n, 1024, thread_count(), ctx, 0.6, 1.0, "smoothing", [&](std::size_t b, std::size_t e) {
    thread_local WindowWalk walk;
    std::size_t own_walks = 0;
    for (std::size_t f = b; f < e; ++f) {
      const double c = values[f];
      const std::uint32_t own = regions.site_of[f];
      if (std::isnan(c) || sites[own] == f) continue;  // a site has its value
      const double t = (c - lo) / step;
      const int below = std::clamp(int(t), 0, bins - 2);
      const double frac = t - below;
      Vec3 d[kMostNear];
      double v[kMostNear], w[kMostNear];
      int m = 0;
      const auto add = [&](std::uint32_t k) {
        const float* row = row_of[k];
        v[m] = (1 - frac) * row[below] + frac * row[below + 1];
        d[m] = site_centre[k] - centre[f];
        ++m;
      };
      add(own);
      for (std::uint32_t k : regions.near_of(own)) add(k);
      double ring = 0;
      std::size_t met = 0;
      for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h)
        if (*h != f) ring += norm(centre[*h] - centre[f]), ++met;
      ring /= double(std::max<std::size_t>(met, 1));
      // Weights that follow the nearest site closely: a plane through
      // sites a few rings apart misses each by about its misfit.
      for (int j = 0; j < m; ++j) w[j] = 1.0 / (dot(d[j], d[j]) / (ring * ring) + 0.25);
      double value = 0;
      Vec3 slope;
      bool sure = m >= 4 && ring > 0 && fit_plane(m, d, v, w, value, slope);
      if (sure) {
        // The plane's misfit, and its change over a ring: a face's window
        // differs from its sites' in shape, not only in place, and by about
        // that much where the values change fast.
        double misfit = 0;
        for (int j = 0; j < m; ++j) misfit = std::max(misfit, std::abs(v[j] - value - dot(slope, d[j])));
        sure = misfit + p.slope_rings * norm(slope) * ring <= tolerance;
      }
      if (sure) {
        out[order[f]] = value;
        continue;
      }
      // Elsewhere the face's own window, binned as the sites' are.
      walk_from(walk, std::uint32_t(f), binning);
      if (walk.summarize()) out[order[f]] = walk.at(c, step);
      ++own_walks;
    }
    walked += own_walks;
  });
  st.exact = walked;
  return true;
}

}  // namespace

void bilateral_smooth_sampled(const Mesh& mesh, const Adjacency& g, std::vector<double>& values, int window,
                              const Context* ctx, const SampledFilterParams& p, SampledFilterStats* stats) {
  SampledFilterStats st;
  const std::size_t n = values.size();
  if (window <= 0) window = default_window(n);
  std::vector<Vec3> centre(n);
  parallel_blocks(n, kSetUpBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) centre[f] = face_centroid(mesh, f);
  });
  const std::vector<std::uint32_t> order = curve_order(centre);
  // The faces renumbered along the curve: their values, centres and graph,
  // as records where no face has more than three neighbours (a closed or
  // bordered manifold mesh: a walk then reads one cache line a face).
  std::size_t degree = 0;
  for (std::size_t f = 0; f < n; ++f) degree = std::max(degree, g.degree(f));
  std::vector<std::uint32_t> rank(n);
  std::vector<double> sorted_values(n);
  std::vector<Vec3> sorted_centre(n);
  parallel_blocks(n, kSetUpBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const std::uint32_t f = order[i];
      rank[f] = std::uint32_t(i);
      sorted_values[i] = values[f], sorted_centre[i] = centre[f];
    }
  });
  if (degree <= 3) {
    std::vector<FaceRecord> record(n);
    parallel_blocks(n, kSetUpBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const std::uint32_t f = order[i];
        FaceRecord& r = record[i];
        r.value = float(sorted_values[i]);
        for (std::size_t j = 0; j < 3; ++j) r.near[j] = j < g.degree(f) ? rank[g.begin(f)[j]] : std::uint32_t(i);
      }
    });
    if (!sampled_pass(sorted_centre, RecordGraph{record.data(), n}, sorted_values, window, ctx, p, st, order.data(),
                      values.data()))
      return;
  } else {
    Adjacency sorted;
    sorted.offsets.resize(n + 1);
    sorted.offsets[0] = 0;
    for (std::size_t i = 0; i < n; ++i) sorted.offsets[i + 1] = sorted.offsets[i] + std::uint32_t(g.degree(order[i]));
    sorted.items.resize(g.items.size());
    parallel_blocks(n, kSetUpBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        std::uint32_t* item = sorted.items.data() + sorted.offsets[i];
        for (const std::uint32_t* h = g.begin(order[i]); h != g.end(order[i]); ++h) *item++ = rank[*h];
      }
    });
    if (!sampled_pass(sorted_centre, sorted, sorted_values, window, ctx, p, st, order.data(), values.data())) return;
  }
  if (stats) *stats = st;
}

}  // namespace cgview::sdf
