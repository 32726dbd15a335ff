// Skeletons and meshes the skeleton tests share (header-only): a circle, a
// capsule, a Y, and metrics printed for a failure's message.
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "registry/registry.h"
#include "test_support.h"

namespace cgview::test {

inline std::string metrics_json_for_test(const Metrics& m) {
  std::string out;
  for (const auto& [k, v] : m) out += k + "=" + std::to_string(v) + " ";
  return out;
}

// A circle of n nodes, radius R, in the z = 0 plane, around (0, 0, 0).
inline Skeleton circle(double R, int n) {
  Skeleton s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * std::numbers::pi * i / n;
    s.nodes.push_back({R * std::cos(a), R * std::sin(a), 0});
    s.edges.push_back({Index(i), Index((i + 1) % n)});
  }
  return s;
}

// A capsule along z: radius r, cylinder from -h/2 to h/2, hemispherical ends.
inline Mesh capsule(double r, double h) {
  std::vector<std::pair<double, double>> profile;
  const int cap = 12, body = 40;
  for (int i = 0; i <= cap; ++i) {
    const double t = std::numbers::pi / 2 * i / cap;
    profile.push_back({r * std::sin(t), h / 2 + r * std::cos(t)});
  }
  for (int i = 1; i < body; ++i) profile.push_back({r, h / 2 - h * i / body});
  for (int i = 0; i <= cap; ++i) {
    const double t = std::numbers::pi / 2 * i / cap;
    profile.push_back({r * std::cos(t), -h / 2 - r * std::sin(t)});
  }
  return revolve(profile, 32);
}

inline Skeleton sample_skeleton() {
  Skeleton s;  // a Y: three branches meeting at node 1, one with a middle node
  s.nodes = {{0, 0, 0}, {0, 1, 0}, {-1, 2, 0.5}, {1, 2, -0.25}, {1.5, 3, 0.125}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {3, 4}};
  return s;
}

}  // namespace cgview::test
