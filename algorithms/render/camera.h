// Cameras for the offscreen renderer: an orbit camera (azimuth, elevation,
// distance around a target, fit to a bounding box by default) or full
// matrices, resolved into the view and projection matrices that a render
// used, with the inverse maps from a pixel (and its depth) back to a 3D
// point or ray.  No GL here: the matrices follow OpenGL's conventions
// (column-major, right-handed eye space looking down -z, NDC in [-1, 1]^3,
// window depth in [0, 1]).
#pragma once

#include <array>
#include <optional>

#include "core/vec.h"

namespace cgview::render {

// A 4x4 matrix, column-major as OpenGL stores it: element (row r, column c)
// is m[c * 4 + r].
struct Mat4 {
  std::array<double, 16> m{};
  double& operator()(int r, int c) { return m[c * 4 + r]; }
  double operator()(int r, int c) const { return m[c * 4 + r]; }
  static Mat4 identity();
};
Mat4 operator*(const Mat4& a, const Mat4& b);
// General inverse (cofactors); throws InvalidInput "camera matrix is singular".
Mat4 inverse(const Mat4& a);
// a * (p, 1) divided by w.
Vec3 transform_point(const Mat4& a, Vec3 p);
Mat4 look_at(Vec3 eye, Vec3 target, Vec3 up);
Mat4 perspective(double fov_y_rad, double aspect, double near, double far);
Mat4 orthographic(double left, double right, double bottom, double top, double near, double far);
Mat4 translation(Vec3 t);

enum class Projection { perspective, orthographic };

// What a caller asks for.  The orbit camera looks at `target` from
//   eye = target + distance * (cos(el) sin(az), sin(el), cos(el) cos(az))
// with +y up: azimuth 0, elevation 0 looks from +z towards -z.
struct Camera {
  Projection projection = Projection::perspective;
  double azimuth = 30;         // degrees around +y
  double elevation = 20;       // degrees above the xz plane, in [-90, 90]
  double distance = 0;         // from the target; 0: fit the bounding sphere in view
  double fov_y = 40;           // degrees, perspective only, in (0, 180)
  std::optional<Vec3> target;  // default: the bounding box's centre
  // Both given: used as they are (the orbit settings are ignored).
  std::optional<Mat4> view, projection_matrix;
};

struct Ray {
  Vec3 origin, direction;  // direction of unit length
};

// The camera of one render, with the maps between pixels and world space.
// Pixel (i, j) is column i from the left, row j from the top; its centre is
// (i + 0.5, j + 0.5).  Depth is OpenGL's window depth in [0, 1] (1: nothing).
struct CameraMatrices {
  Mat4 view, projection;
  int width = 0, height = 0;
  Projection kind = Projection::perspective;

  Mat4 view_projection() const { return projection * view; }
  Vec3 eye() const;      // camera centre (perspective) or a point on the view axis (orthographic)
  Vec3 forward() const;  // unit viewing direction
  // The world point seen at pixel coordinates (x, y) with window depth d.
  Vec3 unproject(double x, double y, double depth) const;
  // The ray through (x, y): from the near plane, along the view direction
  // (orthographic) or away from the eye (perspective).
  Ray ray(double x, double y) const;
  // Pixel coordinates and window depth of a world point.
  Vec3 project(Vec3 p) const;
  // World-space size of one pixel at the target (orthographic: everywhere).
  double pixel_size_at(double distance_from_eye) const;
};

// The matrices of `camera` for an image of width x height showing `box`.
// Throws InvalidInput naming the setting (fov_y, elevation, distance, size).
CameraMatrices resolve_camera(const Camera& camera, const BBox& box, int width, int height);

// An orthographic camera looking at the box's centre from `direction` (a unit
// vector from the centre towards the eye), the bounding sphere filling the
// shorter side of the image; up is +y unless the direction is nearly
// vertical (then +z).
CameraMatrices orthographic_view(Vec3 direction, const BBox& box, int width, int height);

}  // namespace cgview::render
