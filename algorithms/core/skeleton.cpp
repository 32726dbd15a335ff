#include "core/skeleton.h"

#include <numeric>
#include <string>

#include "core/errors.h"
#include "core/union_find.h"

namespace cgview {

void Skeleton::validate() const {
  for (std::size_t i = 0; i < nodes.size(); ++i)
    if (!is_finite(nodes[i])) throw InvalidInput("skeleton node " + std::to_string(i) + " is not finite");
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    if (a >= nodes.size() || b >= nodes.size())
      throw InvalidInput("skeleton edge " + std::to_string(e) + " refers to node " + std::to_string(std::max(a, b)) +
                         " but there are only " + std::to_string(nodes.size()));
    if (a == b)
      throw InvalidInput("skeleton edge " + std::to_string(e) + " joins node " + std::to_string(a) + " to itself");
  }
  if (!radii.empty() && radii.size() != nodes.size())
    throw InvalidInput("skeleton has " + std::to_string(radii.size()) + " radii for " + std::to_string(nodes.size()) +
                       " nodes");
}

Adjacency skeleton_adjacency(const Skeleton& s) {
  Adjacency a;
  a.offsets.assign(s.nodes.size() + 1, 0);
  for (const auto& e : s.edges) {
    ++a.offsets[e[0] + 1];
    ++a.offsets[e[1] + 1];
  }
  std::partial_sum(a.offsets.begin(), a.offsets.end(), a.offsets.begin());
  a.items.resize(a.offsets.back());
  std::vector<std::uint32_t> fill(a.offsets.begin(), a.offsets.end() - 1);
  for (const auto& e : s.edges) {
    a.items[fill[e[0]]++] = e[1];
    a.items[fill[e[1]]++] = e[0];
  }
  return a;
}

std::vector<std::uint32_t> node_degrees(const Skeleton& s) {
  std::vector<std::uint32_t> d(s.nodes.size(), 0);
  for (const auto& e : s.edges) {
    ++d[e[0]];
    ++d[e[1]];
  }
  return d;
}

double total_length(const Skeleton& s) {
  double sum = 0;
  for (const auto& e : s.edges) sum += norm(s.nodes[e[1]] - s.nodes[e[0]]);
  return sum;
}

std::uint32_t skeleton_components(const Skeleton& s, std::vector<std::uint32_t>& component) {
  UnionFind sets(s.nodes.size());
  for (const auto& e : s.edges) sets.unite(e[0], e[1]);
  return sets.labels(component);
}

std::vector<std::vector<Index>> skeleton_branches(const Skeleton& s) {
  const Adjacency adj = skeleton_adjacency(s);
  std::vector<char> used(2 * s.edges.size(), 0);  // each CSR slot is one directed edge
  // Marks the directed slot a->b and its reverse as walked.
  auto mark = [&](Index a, Index b) {
    for (auto o = adj.offsets[a]; o < adj.offsets[a + 1]; ++o)
      if (adj.items[o] == b && !used[o]) {
        used[o] = 1;
        break;
      }
    for (auto o = adj.offsets[b]; o < adj.offsets[b + 1]; ++o)
      if (adj.items[o] == a && !used[o]) {
        used[o] = 1;
        break;
      }
  };
  std::vector<std::vector<Index>> out;
  auto walk = [&](Index start, std::uint32_t slot) {
    std::vector<Index> path{start};
    Index prev = start, cur = adj.items[slot];
    mark(prev, cur);
    path.push_back(cur);
    while (adj.degree(cur) == 2 && cur != start) {
      Index next = adj.items[adj.offsets[cur]] == prev ? adj.items[adj.offsets[cur] + 1] : adj.items[adj.offsets[cur]];
      // Take an unwalked slot (matters for two parallel edges).
      std::uint32_t o = adj.offsets[cur];
      if (used[o]) ++o;
      if (o < adj.offsets[cur + 1] && !used[o]) next = adj.items[o];
      else break;
      mark(cur, next);
      prev = cur;
      cur = next;
      path.push_back(cur);
    }
    out.push_back(std::move(path));
  };
  for (Index v = 0; v < s.nodes.size(); ++v)
    if (adj.degree(v) != 2)
      for (auto o = adj.offsets[v]; o < adj.offsets[v + 1]; ++o)
        if (!used[o]) walk(v, o);
  for (Index v = 0; v < s.nodes.size(); ++v)  // cycles made only of degree-2 nodes
    for (auto o = adj.offsets[v]; o < adj.offsets[v + 1]; ++o)
      if (!used[o]) walk(v, o);
  return out;
}

bool prune_spurs(Skeleton& s,
                 const std::function<bool(const std::vector<Index>& branch, double length, Index tip)>& drop) {
  const std::vector<std::uint32_t> degree = node_degrees(s);
  std::vector<std::uint8_t> unused(s.nodes.size(), 0);
  bool changed = false;
  for (const std::vector<Index>& b : skeleton_branches(s)) {
    if (b.size() < 2 || b.front() == b.back()) continue;
    const bool spur =
        (degree[b.front()] == 1 && degree[b.back()] >= 3) || (degree[b.back()] == 1 && degree[b.front()] >= 3);
    if (!spur) continue;
    double length = 0;
    for (std::size_t k = 1; k < b.size(); ++k) length += norm(s.nodes[b[k]] - s.nodes[b[k - 1]]);
    if (!drop(b, length, degree[b.front()] == 1 ? b.front() : b.back())) continue;
    for (Index n : b)
      if (degree[n] < 3) unused[n] = 1;
    changed = true;
  }
  std::erase_if(s.edges, [&](const std::array<Index, 2>& e) { return unused[e[0]] || unused[e[1]]; });
  return changed;
}

BBox bounding_box(const Skeleton& s) {
  BBox b;
  for (const Vec3& p : s.nodes) b.add(p);
  return b;
}

}  // namespace cgview
