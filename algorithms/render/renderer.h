// The offscreen renderer: one or several meshes drawn into a framebuffer
// object of an EGL context with no window (render/egl_context.h), in the
// viewer's modes, with a scalar field as a colour map and a skeleton as an
// overlay, read back as colour, depth, face ids and a silhouette.
//
// This header includes no EGL or GL header.  A Renderer owns its context; it
// may be used from any thread, one thread at a time (each call makes the
// context current and releases it).  For concurrent rendering use one
// Renderer per thread (or a pool).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "core/skeleton.h"
#include "render/camera.h"
#include "render/egl_context.h"
#include "render/image.h"

namespace cgview::render {

enum class RenderMode { points, wireframe, flat, smooth, toon };
// "points", "wireframe", "flat", "smooth", "toon"; throws InvalidInput naming `what`.
RenderMode parse_render_mode(const std::string& text, const char* what = "mode");
const char* to_string(RenderMode m);

constexpr int kMaxImageSize = 8192;
constexpr std::uint32_t kNoFace = 0xFFFFFFFFu;

// One mesh to draw, with what to show on it.  Pointers must outlive the call.
struct RenderItem {
  const Mesh* mesh = nullptr;
  const ScalarField* field = nullptr;  // colour map (per vertex or per face); nullptr: `color`
  const Skeleton* skeleton = nullptr;  // drawn over the mesh, not hidden by it
  Color color{200, 200, 210, 255};     // the surface colour without a field
};

struct RenderParams {
  int width = 800, height = 600;  // each in [1, 8192]
  RenderMode mode = RenderMode::smooth;
  Camera camera;  // fit to the items' bounding box by default
  Color background{255, 255, 255, 255};
  // What to read back (colour is cheap to skip for algorithms).
  bool color = true, depth = false, face_ids = false, silhouette = false;
  float point_size = 3, line_width = 1;
};

struct RenderResult {
  CameraMatrices camera;     // the matrices used: pixel + depth -> 3D point or ray
  Image color;               // when asked
  std::vector<float> depth;  // window depth in [0, 1] per pixel, rows from the top; 1: nothing
  // Per pixel: the face seen, numbered over all items in order (item k's
  // face f is f + the face counts of items 0..k-1); kNoFace: background.
  // In points and wireframe modes: the face whose point or edge covers the pixel.
  // A mesh with no faces (a point cloud) is drawn as points in every mode,
  // and its "face" ids are vertex indices.
  std::vector<std::uint32_t> face_ids;
  std::vector<std::uint8_t> silhouette;  // 1 where a surface is seen, else 0
};

// GL objects a Renderer holds now (what it generated and has not deleted).
struct GlObjectCounts {
  long buffers = 0, vertex_arrays = 0, textures = 0, framebuffers = 0, renderbuffers = 0, programs = 0;
  long total() const { return buffers + vertex_arrays + textures + framebuffers + renderbuffers + programs; }
  friend bool operator==(const GlObjectCounts&, const GlObjectCounts&) = default;
};

// One orthographic (or any) view's buffers, for algorithms.
struct ViewCapture {
  CameraMatrices camera;
  std::vector<std::uint8_t> silhouette;  // 1 inside, 0 outside; rows from the top
  std::vector<float> depth;              // window depth; 1 outside.  Linear in distance for orthographic views
  std::vector<float> back_depth;         // when asked: the farthest surface's window depth; 1 outside
  std::vector<std::uint32_t> face_ids;   // when asked; kNoFace outside
};

// What a capture reads back besides silhouette and depth.  Back depth (where
// each pixel's ray leaves the shape: an orthographic view and its antipode in
// one drawing) and face ids cannot be asked together.
struct CaptureOptions {
  bool face_ids = false;
  bool back_depth = false;
  // Called after each view is read back, on the thread that drew it
  // (capture_cameras draws with several contexts on threads of their own,
  // so it must be thread-safe): the caller's per-view progress.  What it
  // throws (Cancelled) ends the capture.
  std::function<void()> after_view{};
};

class Renderer {
 public:
  // Starts an EGL context (throws Error when no platform can start one).
  explicit Renderer(GlPlatform platform = GlPlatform::automatic);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws the items.  Throws InvalidInput naming the problem: size (width,
  // height), no items or a mesh with no vertices, a field that does not match its mesh
  // (field), a skeleton that fails validate() (skeleton).
  RenderResult render(const std::vector<RenderItem>& items, const RenderParams& params);
  RenderResult render(const Mesh& mesh, const RenderParams& params) { return render({RenderItem{&mesh}}, params); }

  // The mesh is uploaded once and drawn from each camera; silhouette and depth
  // always, face ids and back depth when asked.  All cameras must have the
  // same size.
  std::vector<ViewCapture> capture(const Mesh& mesh, const std::vector<CameraMatrices>& cameras,
                                   const CaptureOptions& options = {});

  const EglInfo& info() const;
  GlObjectCounts live_objects() const;
  // Asks GL itself (glIsBuffer, ... on every id the renderer ever generated)
  // how many of those objects still exist.
  GlObjectCounts gl_objects_alive();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Checks a requested image size: InvalidInput "width must be in [1, 8192], got 0".
void check_image_size(int width, int height);

}  // namespace cgview::render
