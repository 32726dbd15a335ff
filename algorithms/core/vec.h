// Small fixed-size vectors for geometry that needs no linear-algebra library.
// Eigen is used where linear algebra is needed (see core/eigen.h).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

namespace cgview {

template <class T>
struct Vec3T {
  T x{}, y{}, z{};
  constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr const T& operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  friend constexpr Vec3T operator+(Vec3T a, Vec3T b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3T operator-(Vec3T a, Vec3T b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3T operator*(Vec3T a, T s) { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3T operator*(T s, Vec3T a) { return a * s; }
  friend constexpr Vec3T operator/(Vec3T a, T s) { return {a.x / s, a.y / s, a.z / s}; }
  constexpr Vec3T& operator+=(Vec3T b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  constexpr Vec3T& operator-=(Vec3T b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  constexpr Vec3T& operator*=(T s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  friend constexpr bool operator==(const Vec3T&, const Vec3T&) = default;
};
using Vec3 = Vec3T<double>;
using Vec3f = Vec3T<float>;

struct Vec2f {
  float u{}, v{};
  friend constexpr bool operator==(const Vec2f&, const Vec2f&) = default;
};

// An 8-bit RGBA colour.
struct Color {
  std::uint8_t r{255}, g{255}, b{255}, a{255};
  friend constexpr bool operator==(const Color&, const Color&) = default;
};

template <class T>
constexpr T dot(Vec3T<T> a, Vec3T<T> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
constexpr Vec3T<T> cross(Vec3T<T> a, Vec3T<T> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class T>
T norm(Vec3T<T> a) {
  return std::sqrt(dot(a, a));
}
template <class T>
Vec3T<T> normalized(Vec3T<T> a) {
  T n = norm(a);
  return n > T(0) ? a / n : Vec3T<T>{};
}
template <class T>
bool is_finite(Vec3T<T> a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}
// The point of segment ab nearest to p (a when the segment is a point).
inline Vec3 closest_point_on_segment(Vec3 p, Vec3 a, Vec3 b) {
  const Vec3 ab = b - a;
  const double len2 = dot(ab, ab);
  double t = len2 > 0 ? dot(p - a, ab) / len2 : 0.0;
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  return a + ab * t;
}

inline Vec3f to_float(Vec3 a) { return {float(a.x), float(a.y), float(a.z)}; }
inline Vec3 to_double(Vec3f a) { return {a.x, a.y, a.z}; }

// An axis-aligned box; empty() until a point is added.
struct BBox {
  Vec3 min{HUGE_VAL, HUGE_VAL, HUGE_VAL};
  Vec3 max{-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  bool empty() const { return min.x > max.x; }
  void add(Vec3 p) {
    for (int i = 0; i < 3; ++i) {
      if (p[i] < min[i]) min[i] = p[i];
      if (p[i] > max[i]) max[i] = p[i];
    }
  }
  Vec3 size() const { return empty() ? Vec3{} : max - min; }
  Vec3 center() const { return empty() ? Vec3{} : (min + max) * 0.5; }
  double diagonal() const { return norm(size()); }
};

}  // namespace cgview
