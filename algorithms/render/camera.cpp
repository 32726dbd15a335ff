#include "render/camera.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/errors.h"

namespace cgview::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

double radians(double deg) { return deg * kPi / 180.0; }

struct Sphere {
  Vec3 centre;
  double radius = 1;
};

Sphere bounding_sphere(const BBox& box) {
  if (box.empty()) return {};
  const double r = 0.5 * box.diagonal();
  return {box.center(), r > 0 ? r : 1e-3 * (1.0 + norm(box.center()))};
}

void check_size(int width, int height) {
  if (width <= 0 || height <= 0)
    throw InvalidInput("camera: the image size must be positive, got " + std::to_string(width) + "x" +
                       std::to_string(height));
}

}  // namespace

Mat4 Mat4::identity() {
  Mat4 a;
  for (int i = 0; i < 4; ++i) a(i, i) = 1;
  return a;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 c;
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) {
      double s = 0;
      for (int i = 0; i < 4; ++i) s += a(r, i) * b(i, k);
      c(r, k) = s;
    }
  return c;
}

Mat4 inverse(const Mat4& a) {
  // Gauss-Jordan with partial pivoting on [a | I].
  double w[4][8];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 8; ++c) w[r][c] = c < 4 ? a(r, c) : (c - 4 == r ? 1.0 : 0.0);
  for (int c = 0; c < 4; ++c) {
    int p = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(w[r][c]) > std::abs(w[p][c])) p = r;
    if (std::abs(w[p][c]) < 1e-300) throw InvalidInput("camera: the camera matrix is singular");
    if (p != c)
      for (int k = 0; k < 8; ++k) std::swap(w[p][k], w[c][k]);
    const double inv = 1.0 / w[c][c];
    for (int k = 0; k < 8; ++k) w[c][k] *= inv;
    for (int r = 0; r < 4; ++r)
      if (r != c && w[r][c] != 0) {
        const double f = w[r][c];
        for (int k = 0; k < 8; ++k) w[r][k] -= f * w[c][k];
      }
  }
  Mat4 out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = w[r][c + 4];
  return out;
}

Vec3 transform_point(const Mat4& a, Vec3 p) {
  double v[4];
  for (int r = 0; r < 4; ++r) v[r] = a(r, 0) * p.x + a(r, 1) * p.y + a(r, 2) * p.z + a(r, 3);
  return Vec3{v[0], v[1], v[2]} / v[3];
}

Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up) {
  const Vec3 f = normalized(target - eye);
  const Vec3 s = normalized(cross(f, up));
  const Vec3 u = cross(s, f);
  Mat4 m = Mat4::identity();
  for (int i = 0; i < 3; ++i) {
    m(0, i) = s[i];
    m(1, i) = u[i];
    m(2, i) = -f[i];
  }
  m(0, 3) = -dot(s, eye);
  m(1, 3) = -dot(u, eye);
  m(2, 3) = dot(f, eye);
  return m;
}

Mat4 perspective(double fov_y_rad, double aspect, double near, double far) {
  const double f = 1.0 / std::tan(fov_y_rad / 2);
  Mat4 m;
  m(0, 0) = f / aspect;
  m(1, 1) = f;
  m(2, 2) = (far + near) / (near - far);
  m(2, 3) = 2 * far * near / (near - far);
  m(3, 2) = -1;
  return m;
}

Mat4 orthographic(double l, double r, double b, double t, double n, double f) {
  Mat4 m = Mat4::identity();
  m(0, 0) = 2 / (r - l);
  m(1, 1) = 2 / (t - b);
  m(2, 2) = -2 / (f - n);
  m(0, 3) = -(r + l) / (r - l);
  m(1, 3) = -(t + b) / (t - b);
  m(2, 3) = -(f + n) / (f - n);
  return m;
}

Mat4 translation(Vec3 t) {
  Mat4 m = Mat4::identity();
  m(0, 3) = t.x;
  m(1, 3) = t.y;
  m(2, 3) = t.z;
  return m;
}

Vec3 CameraMatrices::eye() const {
  const Mat4 inv = inverse(view);
  return {inv(0, 3), inv(1, 3), inv(2, 3)};
}

Vec3 CameraMatrices::forward() const { return normalized(Vec3{-view(2, 0), -view(2, 1), -view(2, 2)}); }

Vec3 CameraMatrices::unproject(double x, double y, double depth) const {
  const Vec3 ndc{2 * x / width - 1, 1 - 2 * y / height, 2 * depth - 1};
  return transform_point(inverse(view_projection()), ndc);
}

Ray CameraMatrices::ray(double x, double y) const {
  const Vec3 a = unproject(x, y, 0), b = unproject(x, y, 1);
  return {a, normalized(b - a)};
}

Vec3 CameraMatrices::project(Vec3 p) const {
  const Vec3 ndc = transform_point(view_projection(), p);
  return {(ndc.x + 1) * 0.5 * width, (1 - ndc.y) * 0.5 * height, (ndc.z + 1) * 0.5};
}

double CameraMatrices::pixel_size_at(double d) const {
  // Column 1 of the projection scales eye-space y into NDC.
  const double sy = projection(1, 1);
  if (kind == Projection::orthographic) return 2.0 / (sy * height);
  return 2.0 * d / (sy * height);
}

CameraMatrices resolve_camera(const Camera& cam, const BBox& box, int width, int height) {
  check_size(width, height);
  CameraMatrices out;
  out.width = width;
  out.height = height;
  out.kind = cam.projection;
  if (cam.view && cam.projection_matrix) {
    out.view = *cam.view;
    out.projection = *cam.projection_matrix;
    // The last row of a perspective matrix is (0, 0, -1, 0).
    out.kind = std::abs((*cam.projection_matrix)(3, 3)) < 1e-12 ? Projection::perspective : Projection::orthographic;
    return out;
  }
  if (!(cam.elevation >= -90 && cam.elevation <= 90))
    throw InvalidInput("camera: elevation must be in [-90, 90] degrees, got " + std::to_string(cam.elevation));
  if (!std::isfinite(cam.azimuth)) throw InvalidInput("camera: azimuth must be finite");
  if (!(cam.fov_y > 0 && cam.fov_y < 180))
    throw InvalidInput("camera: fov_y must be in (0, 180) degrees, got " + std::to_string(cam.fov_y));
  if (!(cam.distance >= 0) || !std::isfinite(cam.distance))
    throw InvalidInput("camera: distance must be >= 0 (0: fit), got " + std::to_string(cam.distance));

  Sphere s = bounding_sphere(box);
  const Vec3 target = cam.target ? *cam.target : s.centre;
  // The radius around the target that must stay in view.
  const double r = s.radius + norm(target - s.centre);
  const double az = radians(cam.azimuth), el = radians(cam.elevation);
  const Vec3 dir{std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
  const Vec3 up = std::abs(std::cos(el)) < 1e-6 ? Vec3{-std::sin(az) * dir.y, 0, -std::cos(az) * dir.y} : Vec3{0, 1, 0};
  const double aspect = double(width) / height;

  if (cam.projection == Projection::perspective) {
    const double half_y = radians(cam.fov_y) / 2;
    const double half_x = std::atan(std::tan(half_y) * aspect);
    const double fit = r / std::sin(std::min(half_y, half_x));
    const double d = cam.distance > 0 ? cam.distance : fit;
    const double near = std::max(d - 1.05 * r, 1e-3 * r), far = d + 1.05 * r;
    out.view = look_at(target + dir * d, target, up);
    out.projection = perspective(2 * half_y, aspect, near, far);
  } else {
    const double d = cam.distance > 0 ? cam.distance : 2 * r;
    const double hw = aspect >= 1 ? r * aspect : r, hh = aspect >= 1 ? r : r / aspect;
    out.view = look_at(target + dir * d, target, up);
    out.projection = orthographic(-hw, hw, -hh, hh, d - 1.05 * r, d + 1.05 * r);
  }
  return out;
}

CameraMatrices orthographic_view(Vec3 direction, const BBox& box, int width, int height) {
  check_size(width, height);
  const Vec3 dir = normalized(direction);
  if (norm(dir) == 0) throw InvalidInput("orthographic_view: the direction is zero");
  const Sphere s = bounding_sphere(box);
  const double r = s.radius, aspect = double(width) / height;
  const double hw = aspect >= 1 ? r * aspect : r, hh = aspect >= 1 ? r : r / aspect;
  const Vec3 up = std::abs(dir.y) > 0.99 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
  CameraMatrices out;
  out.width = width;
  out.height = height;
  out.kind = Projection::orthographic;
  out.view = look_at(s.centre + dir * (2 * r), s.centre, up);
  out.projection = orthographic(-hw, hw, -hh, hh, 0.95 * r, 3.05 * r);
  return out;
}

}  // namespace cgview::render
