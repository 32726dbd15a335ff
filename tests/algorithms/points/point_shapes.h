// Clouds sampled on analytic shapes, with their exact outward normals, for
// the point-cloud algorithms' tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/point_cloud.h"

namespace cgview::test {

// n points spread evenly over a sphere (a Fibonacci spiral), normals outward.
inline PointCloud sphere_cloud(std::size_t n, double r = 1.0, Vec3 centre = {0, 0, 0}) {
  PointCloud c;
  const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
  for (std::size_t i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (double(i) + 0.5) / double(n);
    const double s = std::sqrt(1.0 - z * z), t = golden * double(i);
    const Vec3 u{s * std::cos(t), s * std::sin(t), z};
    c.positions.push_back(centre + u * r);
    c.normals.push_back(to_float(u));
  }
  return c;
}

// A torus about z (tube radius r around a circle of radius R) sampled on a
// rings x segments grid in its two angles, normals outward.
inline PointCloud torus_cloud(int rings, int segments, double R = 2.0, double r = 0.7) {
  PointCloud c;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double u = 2 * std::numbers::pi * (i + 0.5 * (j % 2)) / rings, v = 2 * std::numbers::pi * j / segments;
      const Vec3 n{std::cos(v) * std::cos(u), std::cos(v) * std::sin(u), std::sin(v)};
      c.positions.push_back(Vec3{R * std::cos(u), R * std::sin(u), 0} + n * r);
      c.normals.push_back(to_float(n));
    }
  return c;
}

// The angle in degrees between two lines (the sign of either ignored).
inline double line_angle_deg(Vec3 a, Vec3 b) {
  const double c = std::abs(dot(a, b)) / (norm(a) * norm(b));
  return std::acos(std::min(1.0, c)) * 180.0 / std::numbers::pi;
}

}  // namespace cgview::test
