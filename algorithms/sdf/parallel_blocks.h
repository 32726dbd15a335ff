// Work over [0, n) in blocks on every core, for the SDF's passes (rays,
// smoothing): progress and cancellation from the calling thread only.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <thread>

#include "core/threads.h"
#include "registry/registry.h"

namespace cgview::sdf {

// Runs fn(begin, end) over [0, n) in blocks on `threads` threads.  Only the
// calling thread touches ctx (progress, cancellation: a Context need not be
// thread-safe); the others stop at the next block once it is cancelled.
template <class Fn>
void parallel_blocks(std::size_t n, std::size_t block, int threads, const Context* ctx, double from, double to,
                     const char* stage, Fn&& fn) {
  std::atomic<std::size_t> next{0}, done{0};
  std::atomic<bool> stop{false};
  auto work = [&](bool main) {
    for (;;) {
      if (stop.load(std::memory_order_relaxed)) return;
      if (main && ctx) {
        if (ctx->cancelled()) {
          stop = true;
          return;
        }
        ctx->progress(from + (to - from) * double(done.load()) / double(std::max<std::size_t>(n, 1)), stage);
      }
      const std::size_t b = next.fetch_add(block);
      if (b >= n) return;
      const std::size_t e = std::min(n, b + block);
      fn(b, e);
      done += e - b;
    }
  };
  on_threads(threads, [&](int t) { work(t == 0); });
  if (ctx) ctx->check_cancelled();
}

}  // namespace cgview::sdf
