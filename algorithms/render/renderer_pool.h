// Renderers kept for reuse.  Each Renderer is an EGL context; starting one
// and compiling its shaders (llvmpipe compiles them at the first draw) costs
// about 20 ms, as much as drawing 48 small views of a 5k-face mesh.  The
// server's renders (render_service.h) and the extra contexts of
// capture_cameras (views.h) take them from a pool.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

#include "render/renderer.h"

namespace cgview::render {

class RendererPool {
 public:
  // At most `max_out` renderers out at once (take() waits for one to come
  // back; 0: no bound), at most `max_idle` kept between uses.
  explicit RendererPool(GlPlatform platform, int max_out = 0, std::size_t max_idle = 4);
  ~RendererPool();
  RendererPool(const RendererPool&) = delete;
  RendererPool& operator=(const RendererPool&) = delete;

  // An idle renderer, or a new one (throws Error as Renderer does when no
  // EGL platform starts).
  std::unique_ptr<Renderer> take();
  // Back into the pool; one beyond max_idle is destroyed (outside the lock),
  // and null (a renderer given up after an error) frees its place.
  void give_back(std::unique_ptr<Renderer> r);
  // Renderers alive: out and idle.
  int started() const;

 private:
  GlPlatform platform_;
  int max_out_;
  std::size_t max_idle_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::vector<std::unique_ptr<Renderer>> idle_;
  int started_ = 0;
};

// The process's pool for a platform (no bound on renderers out; never
// destroyed: at exit the EGL library may be gone before static destructors run).
RendererPool& shared_pool(GlPlatform platform);

}  // namespace cgview::render
