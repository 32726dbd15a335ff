// Viewpoints spread evenly on a sphere, and the silhouettes and depth
// buffers of a mesh seen from them orthographically: what image-based
// algorithms (skeletons from silhouettes, visual hulls, view-based
// descriptors) start from.  Each capture carries its camera, whose
// unproject(x, y, depth) and ray(x, y) turn a pixel back into a 3D point or
// ray (render/camera.h).
#pragma once

#include <vector>

#include "core/mesh.h"
#include "render/renderer.h"

namespace cgview::render {

enum class SphereSampling { fibonacci, icosahedron };

// n unit directions.  fibonacci: the golden-angle spiral (Gonzalez 2010,
// "Measurement of areas on a sphere using Fibonacci and latitude-longitude
// lattices"), any n >= 1.  icosahedron: the vertices of an icosahedron
// subdivided until it has at least n of them (12, 42, 162, 642, ...), all of
// them returned.  Throws InvalidInput "views must be >= 1".
std::vector<Vec3> sphere_directions(int n, SphereSampling sampling = SphereSampling::fibonacci);

struct ViewsParams {
  int views = 100;  // directions on the sphere (see sphere_directions)
  SphereSampling sampling = SphereSampling::fibonacci;
  int width = 256, height = 256;
  bool face_ids = false;
  // Contexts drawing at once, each on its own thread with its own copy of the
  // mesh (the given renderer is the first).  llvmpipe runs vertex processing
  // and triangle setup on one thread per context, so on a CPU as many
  // contexts as cores render large meshes faster; a GPU needs 1.  The extra
  // contexts are kept for the next call (render::shared_pool,
  // renderer_pool.h): starting one costs about 20 ms on llvmpipe.
  int contexts = 1;
};

// Orthographic silhouettes and depth of the mesh from each direction; the
// bounding sphere fills each image (render/camera.h, orthographic_view).
// Throws InvalidInput for a bad size, view count or contexts < 1.
std::vector<ViewCapture> capture_views(Renderer& renderer, const Mesh& mesh, const ViewsParams& params = {});
// How many contexts to draw with when the caller leaves it to us: 2 on a
// software renderer (llvmpipe's per-context vertex work then runs on two
// cores), 1 on a GPU, where each extra context only adds a copy of the mesh
// and a switch between contexts (docs/BENCHMARKS.md: on an H200, 48 views
// of 256² took 12 ms with one context and 60 ms with two).
int automatic_contexts(const Renderer& renderer);
// The same from cameras of the caller's choosing (all of one size), drawn by
// `contexts` contexts at once, with what `options` asks (Renderer::capture).
std::vector<ViewCapture> capture_cameras(Renderer& renderer, const Mesh& mesh,
                                         const std::vector<CameraMatrices>& cameras, int contexts = 1,
                                         const CaptureOptions& options = {});

}  // namespace cgview::render
