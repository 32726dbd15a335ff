// Renders for the server (GET /api/v1/meshes/{id}/render.png, the viewer's
// thumbnails): a pool of offscreen renderers (render/renderer_pool.h), each
// with its own EGL context, handed to one request at a time.  Requests run on the HTTP worker threads
// (never the I/O threads); at most `max_renderers` render at once, the others
// wait for a free one.  Renderers start on first use, so a server that never
// renders never opens EGL.
#pragma once

#include <string>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "render/renderer_pool.h"

namespace cgview::server {

class RenderService {
 public:
  explicit RenderService(render::GlPlatform platform = render::GlPlatform::automatic, int max_renderers = 2);
  ~RenderService();
  RenderService(const RenderService&) = delete;
  RenderService& operator=(const RenderService&) = delete;

  // The PNG of the mesh (coloured by `field` when given).  Throws
  // InvalidInput (bad parameters) or Error (no EGL platform starts).
  std::string png(const Mesh& mesh, const ScalarField* field, const render::RenderParams& params);

  int renderers_started() const { return pool_.started(); }

 private:
  render::RendererPool pool_;  // at most max_renderers, all kept
};

}  // namespace cgview::server
