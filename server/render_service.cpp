#include "render_service.h"

#include <algorithm>

namespace cgview::server {

RenderService::RenderService(render::GlPlatform platform, int max_renderers)
    : pool_(platform, std::max(1, max_renderers), std::size_t(std::max(1, max_renderers))) {}

RenderService::~RenderService() = default;

std::string RenderService::png(const Mesh& mesh, const ScalarField* field, const render::RenderParams& params) {
  render::check_image_size(params.width, params.height);
  std::unique_ptr<render::Renderer> r = pool_.take();
  render::RenderResult out;
  try {
    out = r->render({render::RenderItem{&mesh, field}}, params);
  } catch (...) {
    pool_.give_back(std::move(r));  // bad parameters: the renderer is sound
    throw;
  }
  pool_.give_back(std::move(r));
  return render::encode_png(out.color);
}

}  // namespace cgview::server
