#include "render_service.h"

#include <algorithm>

namespace cgview::server {

RenderService::RenderService(render::GlPlatform platform, int max_renderers)
    : platform_(platform), max_(std::max(1, max_renderers)) {}

RenderService::~RenderService() = default;

int RenderService::renderers_started() const {
  std::lock_guard lock(mutex_);
  return started_;
}

std::unique_ptr<render::Renderer> RenderService::acquire() {
  std::unique_lock lock(mutex_);
  cv_.wait(lock, [&] { return !idle_.empty() || started_ < max_; });
  if (!idle_.empty()) {
    auto r = std::move(idle_.back());
    idle_.pop_back();
    return r;
  }
  ++started_;
  lock.unlock();
  try {
    return std::make_unique<render::Renderer>(platform_);
  } catch (...) {
    lock.lock();
    --started_;
    cv_.notify_one();
    throw;
  }
}

void RenderService::release(std::unique_ptr<render::Renderer> r) {
  std::lock_guard lock(mutex_);
  idle_.push_back(std::move(r));
  cv_.notify_one();
}

std::string RenderService::png(const Mesh& mesh, const ScalarField* field, const render::RenderParams& params) {
  render::check_image_size(params.width, params.height);
  auto r = acquire();
  render::RenderResult out;
  try {
    out = r->render({render::RenderItem{&mesh, field}}, params);
  } catch (...) {
    release(std::move(r));
    throw;
  }
  release(std::move(r));
  return render::encode_png(out.color);
}

}  // namespace cgview::server
