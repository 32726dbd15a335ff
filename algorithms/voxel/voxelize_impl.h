// The per-triangle loop of voxelize (voxelize.h), a template so that the
// caller's voxel callback inlines.  Read voxelize.h for the rules.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "core/vec.h"

namespace cgview {
namespace voxelize_detail {

// The voxel range [first, last] along one axis whose open slab (i, i + 1)
// a triangle spanning [lo, hi] meets after its shift by -epsilon * n.
inline int first_cell(double lo, double n) {
  const double f = std::floor(lo);
  return f == lo ? (n > 0 ? int(f) - 1 : int(f)) : int(f);
}
inline int last_cell(double hi, double n) {
  const double f = std::floor(hi);
  return f == hi ? (n < 0 ? int(f) : int(f) - 1) : int(f);
}

struct EdgeAxis {
  Vec3 axis;
  double pmin, pmax, r, tol;
};

}  // namespace voxelize_detail

template <class F>
void for_each_triangle_voxel(const Vec3& a, const Vec3& b, const Vec3& c, std::array<int, 3> dims, F&& f) {
  using namespace voxelize_detail;
  const Vec3 n = cross(b - a, c - a);
  if (n.x == 0 && n.y == 0 && n.z == 0) return;  // zero area: covers nothing
  int lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double mn = std::min({a[d], b[d], c[d]}), mx = std::max({a[d], b[d], c[d]});
    if (mx < 0 || mn > dims[d]) return;
    lo[d] = std::max(0, first_cell(mn, n[d]));
    hi[d] = std::min(dims[d] - 1, last_cell(mx, n[d]));
    if (lo[d] > hi[d]) return;
  }
  // Inside one voxel's closed cube, the ranges above already chose the voxel
  // (ties included): the common case of triangles smaller than a voxel.
  if (lo[0] == hi[0] && lo[1] == hi[1] && lo[2] == hi[2]) {
    f(lo[0], lo[1], lo[2]);
    return;
  }
  // The 9 cross products of the box's axes with the triangle's edges.
  EdgeAxis axes[9];
  int m = 0;
  // Rounding in the projections grows with the coordinates' size.
  const double scale = 1.0 + std::max({std::abs(a.x), std::abs(a.y), std::abs(a.z), std::abs(b.x), std::abs(b.y),
                                       std::abs(b.z), std::abs(c.x), std::abs(c.y), std::abs(c.z)});
  const Vec3 edges[3] = {b - a, c - b, a - c};
  for (const Vec3& e : edges) {
    const Vec3 cand[3] = {{0, -e.z, e.y}, {e.z, 0, -e.x}, {-e.y, e.x, 0}};
    for (const Vec3& ax : cand) {
      if (ax.x == 0 && ax.y == 0 && ax.z == 0) continue;
      const double pa = dot(ax, a), pb = dot(ax, b), pc = dot(ax, c);
      const double r = 0.5 * (std::abs(ax.x) + std::abs(ax.y) + std::abs(ax.z));
      axes[m++] = {ax, std::min({pa, pb, pc}), std::max({pa, pb, pc}), r, r * scale * 1e-12};
    }
  }
  const double dplane = dot(n, a);
  const double rplane = 0.5 * (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  const double tol_plane = rplane * scale * 1e-12;
  // Walk the columns along the normal's dominant axis w: in each, only the
  // few voxels the plane crosses are tested.
  const double an[3] = {std::abs(n.x), std::abs(n.y), std::abs(n.z)};
  const int w = an[0] >= an[1] ? (an[0] >= an[2] ? 0 : 2) : (an[1] >= an[2] ? 1 : 2);
  const int u = (w + 1) % 3, v = (w + 2) % 3;
  for (int iu = lo[u]; iu <= hi[u]; ++iu) {
    for (int iv = lo[v]; iv <= hi[v]; ++iv) {
      const double q = n[u] * (iu + 0.5) + n[v] * (iv + 0.5);
      double t0 = (dplane - q - rplane) / n[w], t1 = (dplane - q + rplane) / n[w];
      if (t0 > t1) std::swap(t0, t1);
      t0 = std::floor(t0 - 0.5);
      t1 = std::ceil(t1 - 0.5);
      const int k0 = t0 < lo[w] ? lo[w] : int(t0);
      const int k1 = t1 > hi[w] ? hi[w] : int(t1);
      for (int k = k0; k <= k1; ++k) {
        Vec3 cc;
        cc[u] = iu + 0.5;
        cc[v] = iv + 0.5;
        cc[w] = k + 0.5;
        // On these axes a near tie (within rounding) counts as overlap: a
        // voxel too many rather than a gap.  The exact ties that matter (faces
        // and edges on voxel boundaries) were settled by the ranges above.
        const double p = dplane - dot(n, cc);
        if (p > rplane + tol_plane || p < -rplane - tol_plane) continue;
        bool separated = false;
        for (int t = 0; t < m && !separated; ++t) {
          const EdgeAxis& e = axes[t];
          const double qc = dot(e.axis, cc);
          const double l = e.pmin - qc, h = e.pmax - qc;
          separated = h < -e.r - e.tol || l > e.r + e.tol;
        }
        if (separated) continue;
        int idx[3];
        idx[u] = iu;
        idx[v] = iv;
        idx[w] = k;
        f(idx[0], idx[1], idx[2]);
      }
    }
  }
}

}  // namespace cgview
