#include "skeleton/skeleton_measures.h"

#include <algorithm>
#include <tuple>
#include <cmath>
#include <numbers>

#include "rays/ray_caster.h"

namespace cgview {
namespace {

// Points along every edge, at most `spacing` apart (the nodes included).
std::vector<Vec3> samples_along(const Skeleton& s, double spacing) {
  std::vector<Vec3> out(s.nodes.begin(), s.nodes.end());
  for (const auto& e : s.edges) {
    const Vec3 a = s.nodes[e[0]], b = s.nodes[e[1]];
    const int n = int(std::ceil(norm(b - a) / spacing));
    for (int k = 1; k < n; ++k) out.push_back(a + (b - a) * (double(k) / n));
  }
  return out;
}

double nearest_on(const Skeleton& s, const Vec3& p) {
  double best = HUGE_VAL;
  for (const auto& e : s.edges)
    best = std::min(best, norm(p - closest_point_on_segment(p, s.nodes[e[0]], s.nodes[e[1]])));
  if (s.edges.empty())
    for (const Vec3& q : s.nodes) best = std::min(best, norm(p - q));
  return best;
}

// The directed distances from a's samples to b: the largest and the mean.
std::pair<double, double> directed(const Skeleton& a, const Skeleton& b, double spacing) {
  const std::vector<Vec3> pts = samples_along(a, spacing);
  double largest = 0, sum = 0;
  for (const Vec3& p : pts) {
    const double d = nearest_on(b, p);
    largest = std::max(largest, d);
    sum += d;
  }
  return {largest, pts.empty() ? 0.0 : sum / double(pts.size())};
}

}  // namespace

SkeletonMetrics skeleton_shape_metrics(const Skeleton& s) {
  s.validate();
  SkeletonMetrics m;
  m.nodes = s.num_nodes();
  m.edges = s.num_edges();
  m.branches = skeleton_branches(s).size();
  for (std::uint32_t d : node_degrees(s)) {
    if (d == 1) ++m.endpoints;
    if (d >= 3) ++m.junctions;
  }
  std::vector<std::uint32_t> component;
  m.components = skeleton_components(s, component);
  m.loops = m.edges + m.components - m.nodes;
  m.length = total_length(s);
  return m;
}

SkeletonMetrics measure_skeleton(const Skeleton& s, const Mesh& mesh) {
  SkeletonMetrics m = skeleton_shape_metrics(s);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: a skeleton is measured against a surface");
  if (s.nodes.empty()) return m;
  const RayCaster caster(mesh);
  std::size_t inside = 0;
  for (const Vec3& p : s.nodes) inside += caster.inside(p);
  m.inside_fraction = double(inside) / double(s.nodes.size());

  const Adjacency adj = skeleton_adjacency(s);
  constexpr int kRays = 16;  // 8 chords
  double sum = 0;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (adj.degree(i) != 2) continue;
    const Vec3 p = s.nodes[i];
    const Vec3 t = normalized(s.nodes[adj.items[adj.offsets[i] + 1]] - s.nodes[adj.items[adj.offsets[i]]]);
    if (dot(t, t) == 0) continue;
    const Vec3 helper = std::abs(t.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 u = normalized(cross(t, helper)), v = cross(t, u);
    Vec3 offset{};
    double radius = 0;
    bool ok = true;
    for (int k = 0; k < kRays / 2 && ok; ++k) {
      const double a = std::numbers::pi * k / (kRays / 2);
      const Vec3 d = u * std::cos(a) + v * std::sin(a);
      const RayCaster::Hit h1 = caster.first_hit(p, d), h2 = caster.first_hit(p, d * -1.0);
      if (!h1 || !h2) {
        ok = false;
        break;
      }
      offset += d * ((h1.distance - h2.distance) / 2);
      radius += (h1.distance + h2.distance) / 2;
    }
    if (!ok) continue;
    offset = offset * (2.0 / (kRays / 2));
    radius /= kRays / 2;
    if (!(radius > 0)) continue;
    const double c = norm(offset) / radius;
    sum += c;
    m.centredness_max = std::max(m.centredness_max, c);
    ++m.centredness_nodes;
  }
  if (m.centredness_nodes) m.centredness_mean = sum / double(m.centredness_nodes);
  return m;
}

Metrics metrics_table(const SkeletonMetrics& m) {
  return {{"nodes", double(m.nodes)},
          {"edges", double(m.edges)},
          {"branches", double(m.branches)},
          {"endpoints", double(m.endpoints)},
          {"junctions", double(m.junctions)},
          {"loops", double(m.loops)},
          {"components", double(m.components)},
          {"length", m.length},
          {"inside_fraction", m.inside_fraction},
          {"centredness_nodes", double(m.centredness_nodes)},
          {"centredness_mean", m.centredness_mean},
          {"centredness_max", m.centredness_max}};
}

SkeletonDistance measure_distance(const Skeleton& a, const Skeleton& b, double spacing) {
  a.validate();
  b.validate();
  if (a.nodes.empty() || b.nodes.empty()) throw InvalidInput("a skeleton with no node has no distance to another");
  if (spacing <= 0) {
    BBox box = bounding_box(a);
    const BBox other = bounding_box(b);
    box.add(other.min);
    box.add(other.max);
    spacing = std::max(box.diagonal() / 500.0, 1e-12);
  }
  const auto [hab, mab] = directed(a, b, spacing);
  const auto [hba, mba] = directed(b, a, spacing);
  return {std::max(hab, hba), (mab + mba) / 2};
}

std::size_t endpoints_after_pruning(Skeleton s, double length) {
  return ends_after_pruning(std::move(s), length).size();
}

std::vector<Vec3> ends_after_pruning(Skeleton s, double length) {
  while (prune_spurs(s, [&](const std::vector<Index>&, double l, Index) { return l < length; })) {
  }
  const std::vector<std::uint32_t> degree = node_degrees(s);
  std::vector<Vec3> ends;
  for (std::size_t n = 0; n < degree.size(); ++n)
    if (degree[n] == 1) ends.push_back(s.nodes[n]);
  return ends;
}

std::size_t matched_ends(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double near) {
  std::vector<std::tuple<double, std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t j = 0; j < b.size(); ++j)
      if (const double d = norm(a[i] - b[j]); d <= near) pairs.emplace_back(d, i, j);
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> used_a(a.size()), used_b(b.size());
  std::size_t matched = 0;
  for (const auto& [d, i, j] : pairs)
    if (!used_a[i] && !used_b[j]) used_a[i] = used_b[j] = true, ++matched;
  return matched;
}

}  // namespace cgview
