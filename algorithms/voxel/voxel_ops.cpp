#include "voxel/voxel_ops.h"

#include "core/errors.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

namespace cgview {
namespace {

// Squared distances along one line: d[q] = min_p (q - p)^2 + f[p].
void envelope_1d(const double* f, int n, double* d, int* v, double* z) {
  int k = 0;
  v[0] = 0;
  z[0] = -HUGE_VAL;
  z[1] = HUGE_VAL;
  auto meet = [&](int q, int p) { return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p); };
  for (int q = 1; q < n; ++q) {
    double s = meet(q, v[k]);
    while (s <= z[k]) s = meet(q, v[--k]);  // z[0] = -inf stops it
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = HUGE_VAL;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = q - v[k];
    d[q] = dq * dq + f[v[k]];
  }
}

}  // namespace

VoxelGrid distance_transform(const VoxelGrid& grid, const DistanceTransformParams& params) {
  const auto dims = grid.dims();
  VoxelGrid out(dims, grid.origin(), grid.voxel_size(), VoxelType::float32, grid.size() + 1);
  const std::size_t n = grid.size();
  // Features at 0, the rest "far" (finite, so that differences stay finite).
  constexpr double far = 1e30;
  std::vector<double> f(n);
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const bool occ = grid.type() == VoxelType::float32 ? grid.floats()[i] != 0.f : grid.bytes()[i] != 0;
    const bool feature = params.inside ? !occ : occ;
    f[i] = feature ? 0.0 : far;
    any |= feature;
  }
  if (!any) {
    std::fill(out.floats().begin(), out.floats().end(), std::numeric_limits<float>::infinity());
    return out;
  }
  const int longest = std::max({dims[0], dims[1], dims[2]});
  std::vector<double> line(longest), res(longest), z(longest + 1);
  std::vector<int> v(longest);
  const std::size_t stride[3] = {1, std::size_t(dims[0]), std::size_t(dims[0]) * dims[1]};
  for (int axis = 0; axis < 3; ++axis) {
    const int len = dims[axis];
    const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    for (int p2 = 0; p2 < dims[a2]; ++p2)
      for (int p1 = 0; p1 < dims[a1]; ++p1) {
        const std::size_t base = std::size_t(p1) * stride[a1] + std::size_t(p2) * stride[a2];
        for (int q = 0; q < len; ++q) line[q] = f[base + q * stride[axis]];
        envelope_1d(line.data(), len, res.data(), v.data(), z.data());
        for (int q = 0; q < len; ++q) f[base + q * stride[axis]] = std::min(res[q], far);
      }
  }
  const double s = grid.voxel_size();
  for (std::size_t i = 0; i < n; ++i) out.floats()[i] = float(std::sqrt(f[i]) * s);
  return out;
}

bool is_simple(const VoxelGrid& grid, VoxelIndex v) {
  if (!grid.occupied(v)) return false;
  // The 3x3x3 neighbourhood, cell (a, b, c) in 0..2 at index a + 3b + 9c.
  bool occ[27];
  for (int c = 0; c < 3; ++c)
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) occ[a + 3 * b + 9 * c] = grid.occupied({v.i + a - 1, v.j + b - 1, v.k + c - 1});
  occ[13] = false;
  auto nonzero = [](int n) { return (n % 3 != 1) + ((n / 3) % 3 != 1) + (n / 9 != 1); };
  // Components among the cells `in`, joined when their offsets differ by at
  // most `reach` non-zero coordinates (1: faces, 3: faces, edges and corners).
  auto count = [&](const bool* in, int reach, bool need_face) {
    int seen[27] = {};
    int n = 0;
    for (int s = 0; s < 27; ++s) {
      if (!in[s] || seen[s]) continue;
      int stack[27], top = 0;
      stack[top++] = s;
      seen[s] = 1;
      bool has_face = false;
      while (top) {
        const int x = stack[--top];
        has_face |= nonzero(x) == 1;
        for (int y = 0; y < 27; ++y) {
          if (!in[y] || seen[y]) continue;
          const int da = std::abs(x % 3 - y % 3), db = std::abs((x / 3) % 3 - (y / 3) % 3),
                    dc = std::abs(x / 9 - y / 9);
          if (da > 1 || db > 1 || dc > 1 || (da + db + dc) > reach) continue;
          seen[y] = 1;
          stack[top++] = y;
        }
      }
      if (!need_face || has_face) ++n;
    }
    return n;
  };
  if (count(occ, 3, false) != 1) return false;
  bool background[27];
  for (int s = 0; s < 27; ++s) background[s] = s != 13 && !occ[s] && nonzero(s) <= 2;
  return count(background, 1, true) == 1;
}

VoxelSlice slice(const VoxelGrid& grid, int axis, int index) {
  if (axis < 0 || axis > 2) throw InvalidInput("slice axis must be 0 (x), 1 (y) or 2 (z), got " + std::to_string(axis));
  const auto d = grid.dims();
  if (index < 0 || index >= d[axis])
    throw InvalidInput("slice index " + std::to_string(index) + " is out of range: the grid has " +
                       std::to_string(d[axis]) + " voxels along " + "xyz"[axis] + " (0.." +
                       std::to_string(d[axis] - 1) + ")");
  VoxelSlice out;
  out.axis = axis;
  out.index = index;
  const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;
  out.width = d[a];
  out.height = d[b];
  out.values.resize(std::size_t(out.width) * out.height);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      int p[3];
      p[axis] = index, p[a] = x, p[b] = y;
      out.values[std::size_t(x) + std::size_t(out.width) * y] = grid.get({p[0], p[1], p[2]});
    }
  return out;
}

VoxelGrid threshold(const VoxelGrid& grid, float t) {
  VoxelGrid out(grid.dims(), grid.origin(), grid.voxel_size(), VoxelType::bit, grid.size() + 1);
  auto& o = out.bytes();
  if (grid.type() == VoxelType::float32)
    for (std::size_t i = 0; i < o.size(); ++i) o[i] = grid.floats()[i] > t;
  else
    for (std::size_t i = 0; i < o.size(); ++i) o[i] = float(grid.bytes()[i]) > t;
  return out;
}

std::pair<float, float> value_range(const VoxelGrid& grid) {
  if (grid.size() == 0) return {0.f, 0.f};
  if (grid.type() == VoxelType::float32) {
    const auto [a, b] = std::minmax_element(grid.floats().begin(), grid.floats().end());
    return {*a, *b};
  }
  const auto [a, b] = std::minmax_element(grid.bytes().begin(), grid.bytes().end());
  return {float(*a), float(*b)};
}

Mesh boundary_mesh(const VoxelGrid& grid) {
  const auto d = grid.dims();
  Mesh mesh;
  std::unordered_map<std::uint64_t, Index> vertex_of;
  auto vertex = [&](int x, int y, int z) {
    const std::uint64_t key = (std::uint64_t(x) << 42) | (std::uint64_t(y) << 21) | std::uint64_t(z);
    auto [it, fresh] = vertex_of.try_emplace(key, Index(mesh.positions.size()));
    if (fresh) mesh.positions.push_back(grid.origin() + Vec3{double(x), double(y), double(z)} * grid.voxel_size());
    return it->second;
  };
  auto occ = [&](int x, int y, int z) {
    const VoxelIndex v{x, y, z};
    return grid.contains(v) && grid.get(v) != 0.f;
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;
    const int nu = d[u], nv = d[v];
    std::vector<std::uint8_t> mask(std::size_t(nu) * nv);
    for (int side = 0; side < 2; ++side) {  // 0: faces looking to -a, 1: to +a
      for (int w = 0; w < d[a]; ++w) {
        // Faces of the voxels in layer w on that side.
        for (int jv = 0; jv < nv; ++jv)
          for (int ju = 0; ju < nu; ++ju) {
            int c[3], o[3];
            c[a] = w, c[u] = ju, c[v] = jv;
            o[a] = side ? w + 1 : w - 1, o[u] = ju, o[v] = jv;
            mask[std::size_t(ju) + std::size_t(nu) * jv] = occ(c[0], c[1], c[2]) && !occ(o[0], o[1], o[2]);
          }
        const int plane = side ? w + 1 : w;
        // Greedy rectangles: widest run along u, then as many rows along v.
        for (int jv = 0; jv < nv; ++jv)
          for (int ju = 0; ju < nu;) {
            if (!mask[std::size_t(ju) + std::size_t(nu) * jv]) {
              ++ju;
              continue;
            }
            int wu = 1;
            while (ju + wu < nu && mask[std::size_t(ju + wu) + std::size_t(nu) * jv]) ++wu;
            int hv = 1;
            for (; jv + hv < nv; ++hv) {
              bool full = true;
              for (int t = 0; t < wu && full; ++t) full = mask[std::size_t(ju + t) + std::size_t(nu) * (jv + hv)];
              if (!full) break;
            }
            for (int s = 0; s < hv; ++s)
              std::fill_n(mask.begin() + std::ptrdiff_t(ju + std::size_t(nu) * (jv + s)), wu, 0);
            auto corner = [&](int cu, int cv) {
              int p[3];
              p[a] = plane, p[u] = cu, p[v] = cv;
              return vertex(p[0], p[1], p[2]);
            };
            const Index q0 = corner(ju, jv), q1 = corner(ju + wu, jv), q2 = corner(ju + wu, jv + hv),
                        q3 = corner(ju, jv + hv);
            // (u, v, a) is right-handed: q0 q1 q2 q3 turns counter-clockwise seen from +a.
            if (side) {
              mesh.faces.push_back({q0, q1, q2});
              mesh.faces.push_back({q0, q2, q3});
            } else {
              mesh.faces.push_back({q0, q2, q1});
              mesh.faces.push_back({q0, q3, q2});
            }
            ju += wu;
          }
      }
    }
  }
  return mesh;
}

VoxelTopology voxel_topology(const VoxelGrid& grid) {
  VoxelTopology t;
  std::vector<std::uint32_t> label;
  t.components = grid.components(Connectivity::twenty_six, label);

  // Empty voxels, 6-connected; those touching the border are the outside.
  const auto d = grid.dims();
  VoxelGrid empty(d, grid.origin(), grid.voxel_size(), VoxelType::bit, grid.size() + 1);
  for (std::size_t i = 0; i < grid.size(); ++i) empty.bytes()[i] = label[i] == 0;
  const std::uint32_t ne = empty.components(Connectivity::six, label);
  std::vector<char> touches(ne + 1, 0);
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (!label[i]) continue;
    const VoxelIndex v = grid.unlinear(i);
    if (v.i == 0 || v.j == 0 || v.k == 0 || v.i == d[0] - 1 || v.j == d[1] - 1 || v.k == d[2] - 1)
      touches[label[i]] = 1;
  }
  for (std::uint32_t c = 1; c <= ne; ++c) t.cavities += !touches[c];

  auto occ = [&](int x, int y, int z) {
    const VoxelIndex v{x, y, z};
    return grid.contains(v) && grid.get(v) != 0.f;
  };
  long long V = 0, E = 0, F = 0, C = 0;
  for (int z = 0; z <= d[2]; ++z)
    for (int y = 0; y <= d[1]; ++y)
      for (int x = 0; x <= d[0]; ++x) {
        if (occ(x, y, z)) ++C;
        // Lattice point (x, y, z): any of the 8 voxels around it.
        bool any = false;
        for (int c = 0; c < 8 && !any; ++c) any = occ(x - (c & 1), y - ((c >> 1) & 1), z - ((c >> 2) & 1));
        V += any;
        // Edges from (x, y, z) along each axis: the 4 voxels around them.
        for (int a = 0; a < 3; ++a) {
          const int u = (a + 1) % 3, v = (a + 2) % 3;
          bool e = false;
          for (int c = 0; c < 4 && !e; ++c) {
            int p[3] = {x, y, z};
            p[u] -= c & 1;
            p[v] -= (c >> 1) & 1;
            e = occ(p[0], p[1], p[2]);
          }
          E += e;
          // The face at (x, y, z) perpendicular to a: the 2 voxels on its sides.
          int p[3] = {x, y, z};
          bool f = occ(p[0], p[1], p[2]);
          p[a] -= 1;
          f = f || occ(p[0], p[1], p[2]);
          F += f;
        }
      }
  t.euler = V - E + F - C;
  const long long b1 = (long long)t.components + (long long)t.cavities - t.euler;
  t.tunnels = b1 > 0 ? std::size_t(b1) : 0;
  return t;
}

}  // namespace cgview
