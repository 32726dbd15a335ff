#include "chaos/measures.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>

namespace cgview::chaos {

std::array<double, 3> adjacent_correlation(const std::vector<Vec3>& p) {
  std::array<double, 3> out{0, 0, 0};
  if (p.size() < 3) return out;
  const double m = double(p.size() - 1);
  for (int a = 0; a < 3; ++a) {
    double sx = 0, sy = 0;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) sx += p[i][a], sy += p[i + 1][a];
    const double mx = sx / m, my = sy / m;
    double cxy = 0, cxx = 0, cyy = 0;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
      const double dx = p[i][a] - mx, dy = p[i + 1][a] - my;
      cxy += dx * dy, cxx += dx * dx, cyy += dy * dy;
    }
    out[std::size_t(a)] = cxx > 0 && cyy > 0 ? cxy / std::sqrt(cxx * cyy) : 0.0;
  }
  return out;
}

namespace {

// A static kd-tree over points, stored as an implicit balanced tree: the
// median of idx[lo, hi) sits at mid and splits on the widest axis.
class KdTree {
 public:
  explicit KdTree(const std::vector<Vec3>& pts) : p_(pts), idx_(pts.size()), axis_(pts.size()) {
    std::iota(idx_.begin(), idx_.end(), 0u);
    build(0, idx_.size());
  }
  double nearest_sq(const Vec3& q) const {
    double best = std::numeric_limits<double>::infinity();
    search(q, 0, idx_.size(), best, -1.0);
    return best;
  }
  // Whether a point lies closer than sqrt(r2): stops at the first one found.
  bool any_within(const Vec3& q, double r2) const {
    double best = r2;
    search(q, 0, idx_.size(), best, r2);
    return best < r2;
  }

 private:
  const std::vector<Vec3>& p_;
  std::vector<std::uint32_t> idx_;
  std::vector<std::uint8_t> axis_;

  void build(std::size_t lo, std::size_t hi) {
    if (hi - lo <= 1) return;
    BBox box;
    for (std::size_t i = lo; i < hi; ++i) box.add(p_[idx_[i]]);
    const Vec3 s = box.size();
    const int a = s.x >= s.y && s.x >= s.z ? 0 : s.y >= s.z ? 1 : 2;
    const std::size_t mid = lo + (hi - lo) / 2;
    std::nth_element(idx_.begin() + std::ptrdiff_t(lo), idx_.begin() + std::ptrdiff_t(mid),
                     idx_.begin() + std::ptrdiff_t(hi),
                     [&](std::uint32_t u, std::uint32_t v) { return p_[u][a] < p_[v][a]; });
    axis_[mid] = std::uint8_t(a);
    build(lo, mid);
    build(mid + 1, hi);
  }

  // Nearest squared distance into best; with stop_below > 0, returns as soon
  // as best < stop_below.
  void search(const Vec3& q, std::size_t lo, std::size_t hi, double& best, double stop_below) const {
    if (lo >= hi || best < stop_below) return;
    const std::size_t mid = lo + (hi - lo) / 2;
    const Vec3& m = p_[idx_[mid]];
    const Vec3 d = q - m;
    best = std::min(best, dot(d, d));
    if (hi - lo == 1) return;
    const int a = axis_[mid];
    const double diff = q[a] - m[a];
    if (diff < 0) {
      search(q, lo, mid, best, stop_below);
      if (diff * diff < best) search(q, mid + 1, hi, best, stop_below);
    } else {
      search(q, mid + 1, hi, best, stop_below);
      if (diff * diff < best) search(q, lo, mid, best, stop_below);
    }
  }
};

// Exact, with the early break of Taha and Hanbury (2015): a query with some
// point closer than the largest distance so far cannot raise it, so its
// search stops there; visiting the queries in a scattered order makes that
// largest distance grow early.  Without it, a cipher crowded into a small
// region (every point about as far from a query) costs O(n) per query.
double directed(const std::vector<Vec3>& from, const KdTree& to) {
  double worst = 0;
  const std::size_t n = from.size();
  std::size_t stride = 7919;  // a prime: coprime with n unless n is a multiple of it
  while (n % stride == 0 && stride < n) stride += 2;
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k, i = (i + stride) % n) {
    if (worst > 0 && to.any_within(from[i], worst)) continue;
    worst = std::max(worst, to.nearest_sq(from[i]));
  }
  return std::sqrt(worst);
}

}  // namespace

double hausdorff_vertices(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.empty() || b.empty()) return std::numeric_limits<double>::infinity();
  const KdTree ta(a), tb(b);
  return std::max(directed(a, tb), directed(b, ta));
}

double changed_share(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() != b.size()) return 1.0;
  if (a.empty()) return 0.0;
  std::size_t changed = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      const float x = float(a[i][k]), y = float(b[i][k]);
      changed += std::memcmp(&x, &y, 4) != 0;
    }
  return double(changed) / double(3 * a.size());
}

Displacement displacement(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  Displacement d;
  if (a.empty() || a.size() != b.size()) return d;
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const double e = norm(b[i] - a[i]);
    sum += e * e;
    d.max = std::max(d.max, e);
  }
  d.rms = std::sqrt(sum / double(a.size()));
  return d;
}

double snr_db(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  Vec3 c{};
  for (const Vec3& p : a) c += p;
  if (!a.empty()) c = c / double(a.size());
  double signal = 0, noise = 0;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const Vec3 s = a[i] - c, e = b[i] - a[i];
    signal += dot(s, s), noise += dot(e, e);
  }
  return noise > 0 ? 10.0 * std::log10(signal / noise) : std::numeric_limits<double>::infinity();
}

std::string flip_one_bit(std::string key) {
  if (!key.empty()) key.back() = char(key.back() ^ 1);
  return key;
}

}  // namespace cgview::chaos
