#include "render/renderer_pool.h"

#include <map>

namespace cgview::render {

RendererPool::RendererPool(GlPlatform platform, int max_out, std::size_t max_idle)
    : platform_(platform), max_out_(max_out), max_idle_(max_idle) {}

RendererPool::~RendererPool() = default;

std::unique_ptr<Renderer> RendererPool::take() {
  std::unique_lock lock(mutex_);
  cv_.wait(lock, [&] { return !idle_.empty() || max_out_ <= 0 || started_ < max_out_; });
  if (!idle_.empty()) {
    std::unique_ptr<Renderer> r = std::move(idle_.back());
    idle_.pop_back();
    return r;
  }
  ++started_;
  lock.unlock();
  try {
    return std::make_unique<Renderer>(platform_);
  } catch (...) {
    lock.lock();
    --started_;
    cv_.notify_one();
    throw;
  }
}

void RendererPool::give_back(std::unique_ptr<Renderer> r) {
  {
    std::lock_guard lock(mutex_);
    if (r && idle_.size() < max_idle_) {
      idle_.push_back(std::move(r));
    } else {
      --started_;
    }
    cv_.notify_one();
  }
  r.reset();  // a surplus renderer, destroyed outside the lock
}

int RendererPool::started() const {
  std::lock_guard lock(mutex_);
  return started_;
}

RendererPool& shared_pool(GlPlatform platform) {
  static std::mutex mutex;
  static auto* pools = new std::map<GlPlatform, std::unique_ptr<RendererPool>>;
  std::lock_guard lock(mutex);
  std::unique_ptr<RendererPool>& p = (*pools)[platform];
  if (!p) p = std::make_unique<RendererPool>(platform);
  return *p;
}

}  // namespace cgview::render
