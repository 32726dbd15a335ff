// Work split over a few threads by the caller: f(t) for t = 0 .. threads - 1,
// t = 0 on the calling thread, each other on a thread of its own; returns
// once all have.  f must not throw on the other threads (pass errors back
// through shared state, as the callers' cancellation flags do).
#pragma once

#include <thread>
#include <vector>

namespace cgview {

template <class F>
void on_threads(int threads, const F& f) {
  std::vector<std::jthread> pool;  // joined when this returns, or unwinds
  for (int t = 1; t < threads; ++t) pool.emplace_back(f, t);
  f(0);
}

}  // namespace cgview
