#include "core/cluster_decimate.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

#include "core/errors.h"

namespace cgview {

namespace {

// One clustering pass at cell size h.
Mesh cluster(const Mesh& in, const BBox& box, double h) {
  const auto cells_along = [&](int a) { return std::uint64_t(std::floor((box.max[a] - box.min[a]) / h)) + 1; };
  const std::uint64_t nx = cells_along(0), ny = cells_along(1);
  const auto cell_of = [&](const Vec3& p) {
    std::uint64_t c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::uint64_t(std::max(0.0, std::floor((p[a] - box.min[a]) / h)));
    return c[0] + nx * (c[1] + ny * c[2]);
  };
  // The cluster of each vertex, numbered in order of first use.
  std::unordered_map<std::uint64_t, Index> cluster_of_cell;
  cluster_of_cell.reserve(in.num_vertices() / 4 + 16);
  std::vector<Index> cluster_of(in.num_vertices());
  std::vector<Vec3> sum;
  std::vector<std::uint32_t> count;
  std::vector<std::array<double, 4>> color_sum;
  const bool colors = in.has_colors();
  for (std::size_t v = 0; v < in.num_vertices(); ++v) {
    const auto [it, added] = cluster_of_cell.try_emplace(cell_of(in.positions[v]), Index(sum.size()));
    if (added) {
      sum.push_back({});
      count.push_back(0);
      if (colors) color_sum.push_back({});
    }
    const Index c = it->second;
    cluster_of[v] = c;
    sum[c] += in.positions[v];
    ++count[c];
    if (colors) {
      const Color& k = in.colors[v];
      color_sum[c][0] += k.r, color_sum[c][1] += k.g, color_sum[c][2] += k.b, color_sum[c][3] += k.a;
    }
  }
  Mesh out;
  // Faces first: only clusters that some kept face uses become vertices.
  struct TriHash {
    std::size_t operator()(const Tri& t) const {
      return std::hash<std::uint64_t>()((std::uint64_t(t[0]) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(t[1]) << 21) ^
                                        t[2]);
    }
  };
  std::unordered_set<Tri, TriHash> seen;
  std::vector<Index> vertex_of(sum.size(), Index(-1));
  for (const Tri& t : in.faces) {
    const Tri c{cluster_of[t[0]], cluster_of[t[1]], cluster_of[t[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) continue;
    // One copy of a triangle whatever its orientation or starting corner.
    Tri key = c;
    std::sort(key.begin(), key.end());
    if (!seen.insert(key).second) continue;
    Tri f;
    for (int k = 0; k < 3; ++k) {
      Index& v = vertex_of[c[k]];
      if (v == Index(-1)) {
        v = Index(out.positions.size());
        out.positions.push_back(sum[c[k]] / double(count[c[k]]));
        if (colors) {
          const auto& s = color_sum[c[k]];
          const double n = count[c[k]];
          out.colors.push_back({std::uint8_t(std::lround(s[0] / n)), std::uint8_t(std::lround(s[1] / n)),
                                std::uint8_t(std::lround(s[2] / n)), std::uint8_t(std::lround(s[3] / n))});
        }
      }
      f[k] = v;
    }
    out.faces.push_back(f);
  }
  return out;
}

}  // namespace

ClusterDecimateResult cluster_decimate(const Mesh& mesh, const ClusterDecimateParams& params) {
  if (params.target_faces == 0) throw InvalidInput("cluster_decimate: target_faces must be at least 1");
  mesh.validate();
  ClusterDecimateResult r;
  if (mesh.num_faces() <= params.target_faces) {
    r.mesh.positions = mesh.positions;
    r.mesh.faces = mesh.faces;
    r.mesh.colors = mesh.colors;
    return r;
  }
  const BBox box = bounding_box(mesh);
  // A surface of area A cut by cells of side h meets about A / h^2 cells, and
  // a closed triangle mesh has about twice as many faces as vertices: start
  // from h = sqrt(2 A / target) and grow h until few enough faces remain.
  double area = 0.0;
  for (double a : face_areas(mesh)) area += a;
  double diagonal = 0.0;
  for (int a = 0; a < 3; ++a) diagonal = std::max(diagonal, box.max[a] - box.min[a]);
  double h = area > 0.0 ? std::sqrt(2.0 * area / double(params.target_faces)) : diagonal / 16.0;
  if (!(h > 0.0)) h = 1.0;  // a mesh collapsed to a point
  for (int pass = 0;; ++pass) {
    r.mesh = cluster(mesh, box, h);
    r.cell_size = h;
    if (r.mesh.num_faces() <= params.target_faces) return r;
    // Faces scale as 1 / h^2; aim a little below the target.
    h *= std::sqrt(double(r.mesh.num_faces()) / (0.9 * double(params.target_faces)));
    if (pass > 30) break;  // cannot happen: one cell keeps no face
  }
  return r;
}

}  // namespace cgview
