// Work split over a few threads by the caller: f(t) for t = 0 .. threads - 1,
// t = 0 on the calling thread, each other on a thread of its own; returns
// once all have.  f must not throw on the other threads (pass errors back
// through shared state, as the callers' cancellation flags do).
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <type_traits>
#include <vector>

namespace cgview {

// The machine's cores, at least one.
inline int thread_count() { return std::max(1, int(std::thread::hardware_concurrency())); }

template <class F>
void on_threads(int threads, const F& f) {
  std::vector<std::jthread> pool;  // joined when this returns, or unwinds
  for (int t = 1; t < threads; ++t) pool.emplace_back(f, t);
  f(0);
}

// A pass that reads each of its items once: a thread for each 64k items at
// most (below that a thread's start, tens of microseconds, costs more than
// its share of the pass saves).
inline constexpr std::size_t kItemsPerThread = 65536;

// The threads to split `items` over: one for each `per_thread` of
// them at most (a thread costs tens of microseconds to start), `most` at
// most, at least one.
inline int threads_for(std::size_t items, std::size_t per_thread, int most = thread_count()) {
  return int(std::clamp<std::size_t>(items / per_thread, 1, std::size_t(std::max(1, most))));
}

// f(begin, end) over [0, n) in `threads` equal shares, share t on thread t
// (on_threads: share 0 on the calling thread); f(t, begin, end) where f
// wants to know which share it has.
template <class F>
void on_shares(std::size_t n, int threads, const F& f) {
  const std::size_t parts = std::size_t(std::max(1, threads));
  on_threads(int(parts), [&](int t) {
    const std::size_t begin = n * std::size_t(t) / parts, end = n * std::size_t(t + 1) / parts;
    if constexpr (std::is_invocable_v<const F&, int, std::size_t, std::size_t>) f(t, begin, end);
    else f(begin, end);
  });
}

}  // namespace cgview
