#include "core/mesh.h"

#include <algorithm>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/errors.h"
#include "core/threads.h"
#include "core/union_find.h"

namespace cgview {

namespace {
constexpr Index kNone = std::numeric_limits<Index>::max();

void check_index_triangles(const std::vector<Tri>& tris, std::size_t count, const char* what) {
  for (std::size_t f = 0; f < tris.size(); ++f)
    for (Index i : tris[f])
      if (i >= count)
        throw InvalidInput("face " + std::to_string(f) + " refers to " + what + " " + std::to_string(i) +
                           " but there are only " + std::to_string(count));
}

// Builds a CSR list from (key, value) pairs whose keys are < n, by counting sort.
template <class Pairs>
Adjacency bucket(std::size_t n, std::size_t m, Pairs&& for_each_pair) {
  Adjacency a;
  a.offsets.assign(n + 1, 0);
  for_each_pair([&](std::uint32_t k, std::uint32_t) { ++a.offsets[k + 1]; });
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.items.resize(m);
  std::vector<std::uint32_t> fill(a.offsets.begin(), a.offsets.end() - 1);
  for_each_pair([&](std::uint32_t k, std::uint32_t v) { a.items[fill[k]++] = v; });
  return a;
}

double corner_angle(Vec3 a, Vec3 b, Vec3 c) {  // angle at a
  Vec3 u = b - a, v = c - a;
  return std::atan2(norm(cross(u, v)), dot(u, v));
}
}  // namespace

void Mesh::validate() const {
  for (std::size_t v = 0; v < positions.size(); ++v)
    if (!is_finite(positions[v])) throw InvalidInput("vertex " + std::to_string(v) + " has a non-finite coordinate");
  check_index_triangles(faces, positions.size(), "vertex");
  if (!colors.empty() && colors.size() != positions.size())
    throw InvalidInput("there are " + std::to_string(colors.size()) + " colours for " +
                       std::to_string(positions.size()) + " vertices");
  auto check_attr = [&](std::size_t n, const std::vector<Tri>& idx, const char* what) {
    if (n == 0) return;
    if (idx.empty()) {
      if (n != positions.size())
        throw InvalidInput(std::string("there are ") + std::to_string(n) + " " + what + "s for " +
                           std::to_string(positions.size()) + " vertices");
    } else {
      if (idx.size() != faces.size()) throw InvalidInput(std::string(what) + " index triangles do not match the faces");
      check_index_triangles(idx, n, what);
    }
  };
  check_attr(normals.size(), normal_faces, "normal");
  check_attr(uvs.size(), uv_faces, "uv");
}

BBox bounding_box(const Mesh& mesh) {
  BBox box;
  for (const Vec3& p : mesh.positions) box.add(p);
  return box;
}

std::vector<double> face_areas(const Mesh& mesh) {
  std::vector<double> out(mesh.faces.size());
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) out[f] = 0.5 * norm(face_cross(mesh, f));
  return out;
}

std::vector<Vec3> face_normals(const Mesh& mesh) {
  std::vector<Vec3> out(mesh.faces.size());
  on_shares(out.size(), threads_for(out.size(), kItemsPerThread), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) out[f] = normalized(face_cross(mesh, f));
  });
  return out;
}

double signed_volume(const Mesh& mesh) {
  const auto& P = mesh.positions;
  double six_v = 0;
  for (const Tri& t : mesh.faces) six_v += dot(P[t[0]], cross(P[t[1]], P[t[2]]));
  return six_v / 6.0;
}

std::vector<Vec3> vertex_normals(const Mesh& mesh, NormalWeighting w) {
  std::vector<Vec3> out(mesh.positions.size());
  const auto& P = mesh.positions;
  for (const Tri& t : mesh.faces) {
    Vec3 n2 = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);  // length: twice the area
    Vec3 n = normalized(n2);
    for (int k = 0; k < 3; ++k) {
      double weight = 1.0;
      if (w == NormalWeighting::area) weight = 0.5 * norm(n2);
      else if (w == NormalWeighting::angle) weight = corner_angle(P[t[k]], P[t[(k + 1) % 3]], P[t[(k + 2) % 3]]);
      out[t[k]] += n * weight;
    }
  }
  for (Vec3& n : out) n = normalized(n);
  return out;
}

Adjacency vertex_faces(const Mesh& mesh) {
  const auto& F = mesh.faces;
  return bucket(mesh.positions.size(), 3 * F.size(), [&](auto&& emit) {
    for (std::uint32_t f = 0; f < F.size(); ++f)
      for (Index v : F[f]) emit(v, f);
  });
}

Adjacency vertex_neighbors(const Mesh& mesh) {
  const auto& F = mesh.faces;
  Adjacency a = bucket(mesh.positions.size(), 6 * F.size(), [&](auto&& emit) {
    for (const Tri& t : F)
      for (int k = 0; k < 3; ++k) {
        emit(t[k], t[(k + 1) % 3]);
        emit(t[(k + 1) % 3], t[k]);
      }
  });
  // Sort and deduplicate each list in place, compacting the CSR arrays.
  std::uint32_t out = 0;
  std::uint32_t begin = 0;
  for (std::size_t v = 0; v + 1 < a.offsets.size(); ++v) {
    std::uint32_t end = a.offsets[v + 1];
    auto first = a.items.begin() + begin, last = a.items.begin() + end;
    std::sort(first, last);
    last = std::unique(first, last);
    a.offsets[v] = out;
    for (auto it = first; it != last; ++it)
      if (*it != v) a.items[out++] = *it;
    begin = end;
  }
  a.offsets.back() = out;
  a.items.resize(out);
  return a;
}

EdgeTopology edge_topology(const Mesh& mesh) {
  const auto& F = mesh.faces;
  const std::size_t nv = mesh.positions.size();
  // Face sides bucketed by their smaller end, then sorted by the larger one.
  struct Side {
    Index other;
    std::uint32_t face_corner;
  };  // face*3 + k
  std::vector<std::uint32_t> offsets(nv + 1, 0);
  for (const Tri& t : F)
    for (int k = 0; k < 3; ++k) {
      Index a = t[k], b = t[(k + 1) % 3];
      if (a != b) ++offsets[std::min(a, b) + 1];
    }
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  std::vector<Side> sides(offsets.back());
  std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
  for (std::uint32_t f = 0; f < F.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      Index a = F[f][k], b = F[f][(k + 1) % 3];
      if (a != b) sides[fill[std::min(a, b)]++] = {std::max(a, b), f * 3 + std::uint32_t(k)};
    }

  // Each vertex's sides sorted and its edges counted, then the edges
  // numbered in the vertices' order and written: both with the vertices
  // split over the cores (each writes its own sides, edges and face
  // corners).
  const int threads = threads_for(F.size(), kItemsPerThread);
  std::vector<std::uint32_t> first_edge(nv + 1, 0);
  on_shares(nv, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      const auto first = sides.begin() + offsets[v], last = sides.begin() + offsets[v + 1];
      std::sort(first, last, [](const Side& x, const Side& y) {
        return x.other != y.other ? x.other < y.other : x.face_corner < y.face_corner;
      });
      std::uint32_t edges = 0;
      for (auto it = first; it != last; ++it) edges += it == first || it->other != (it - 1)->other;
      first_edge[v + 1] = edges;
    }
  });
  std::partial_sum(first_edge.begin(), first_edge.end(), first_edge.begin());

  EdgeTopology topo;
  topo.face_edges.assign(F.size(), {kNone, kNone, kNone});
  topo.edges.resize(first_edge[nv]);
  // An edge's faces are its sides' in their sorted order.
  topo.edge_faces.offsets.resize(first_edge[nv] + 1);
  topo.edge_faces.offsets[first_edge[nv]] = std::uint32_t(sides.size());
  topo.edge_faces.items.resize(sides.size());
  on_shares(nv, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v) {
      Index e = first_edge[v];
      for (std::uint32_t k = offsets[v]; k < offsets[v + 1]; ++k) {
        const Side& side = sides[k];
        if (k == offsets[v] || side.other != sides[k - 1].other) {
          if (k != offsets[v]) ++e;
          topo.edges[e] = {Index(v), side.other};
          topo.edge_faces.offsets[e] = k;
        }
        topo.face_edges[side.face_corner / 3][side.face_corner % 3] = e;
        topo.edge_faces.items[k] = side.face_corner / 3;
      }
    }
  });
  return topo;
}

Adjacency face_neighbors(const Mesh& mesh, const EdgeTopology& topo) {
  const std::size_t n = mesh.faces.size();
  Adjacency a;
  a.offsets.assign(n + 1, 0);
  // Both passes with the faces split over the cores (each face writes its
  // own count, then its own list): they read the edges' lists in no order,
  // a cache miss or two a side, 0.1 s on one core for 1.42M faces.
  const int threads = threads_for(n, kItemsPerThread);
  on_shares(n, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      std::uint32_t count = 0;
      // Count the entries written below (a face listed twice on one edge,
      // as one with a collapsed side is, must not leave empty slots).
      for (Index e : topo.face_edges[f])
        if (e != kNone)
          for (auto g = topo.edge_faces.begin(e); g != topo.edge_faces.end(e); ++g) count += *g != f;
      a.offsets[f + 1] = count;
    }
  });
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.items.resize(a.offsets.back());
  on_shares(n, threads, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f) {
      std::uint32_t o = a.offsets[f];
      for (Index e : topo.face_edges[f]) {
        if (e == kNone) continue;
        for (auto g = topo.edge_faces.begin(e); g != topo.edge_faces.end(e); ++g)
          if (*g != f) a.items[o++] = *g;
      }
    }
  });
  return a;
}

std::uint32_t vertex_components(const Mesh& mesh, std::vector<std::uint32_t>& component) {
  UnionFind sets(mesh.positions.size());
  for (const Tri& t : mesh.faces)
    for (int k = 1; k < 3; ++k) sets.unite(t[0], t[k]);
  return sets.labels(component);
}

Mesh with_per_vertex_attributes(const Mesh& mesh) {
  if (mesh.attributes_per_vertex()) return mesh;
  Mesh out;
  out.faces.resize(mesh.faces.size());
  // A new vertex for each distinct (position, normal, uv) corner.
  struct Key {
    Index p, n, t;
    bool operator==(const Key&) const = default;
  };
  struct Hash {
    std::size_t operator()(const Key& k) const {
      return (std::size_t(k.p) * 0x9E3779B97F4A7C15ull) ^ (std::size_t(k.n) * 0xC2B2AE3D27D4EB4Full) ^
             (std::size_t(k.t) * 0x165667B19E3779F9ull);
    }
  };
  std::unordered_map<Key, Index, Hash> ids;
  ids.reserve(mesh.positions.size() * 2);
  const bool has_n = mesh.has_normals(), has_t = mesh.has_uvs();
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      Index p = mesh.faces[f][k];
      Index n = !has_n ? kNone : (mesh.normal_faces.empty() ? p : mesh.normal_faces[f][k]);
      Index t = !has_t ? kNone : (mesh.uv_faces.empty() ? p : mesh.uv_faces[f][k]);
      auto [it, fresh] = ids.try_emplace(Key{p, n, t}, Index(out.positions.size()));
      if (fresh) {
        out.positions.push_back(mesh.positions[p]);
        if (has_n) out.normals.push_back(mesh.normals[n]);
        if (has_t) out.uvs.push_back(mesh.uvs[t]);
        if (mesh.has_colors()) out.colors.push_back(mesh.colors[p]);
      }
      out.faces[f][k] = it->second;
    }
  return out;
}

Mesh subdivide_midpoint(const Mesh& mesh) {
  EdgeTopology topo = edge_topology(mesh);
  Mesh out;
  const Index nv = Index(mesh.positions.size());
  out.positions = mesh.positions;
  out.positions.reserve(nv + topo.edges.size());
  for (const auto& e : topo.edges) out.positions.push_back((mesh.positions[e[0]] + mesh.positions[e[1]]) * 0.5);
  out.faces.reserve(mesh.faces.size() * 4);
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    const auto& fe = topo.face_edges[f];
    if (fe[0] == kNone || fe[1] == kNone || fe[2] == kNone) {  // degenerate: keep as is
      out.faces.push_back(t);
      continue;
    }
    Index m01 = nv + fe[0], m12 = nv + fe[1], m20 = nv + fe[2];
    out.faces.push_back({t[0], m01, m20});
    out.faces.push_back({t[1], m12, m01});
    out.faces.push_back({t[2], m20, m12});
    out.faces.push_back({m01, m12, m20});
  }
  return out;
}

}  // namespace cgview
