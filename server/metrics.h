// What a lab's admin watches: GET /metrics in Prometheus' text format, on
// prometheus-cpp's metric types and text serializer (Debian's
// prometheus-cpp-dev), served by the router like any route (its separate
// pull server is not used).  Counters and histograms are updated where
// things happen; gauges (jobs by state, queue, store) are read when scraped.
#pragma once

#include <chrono>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <set>
#include <string>
#include <utility>

namespace prometheus {
class Registry;
class Counter;
class Gauge;
class Histogram;
template <typename T>
class Family;
}  // namespace prometheus

namespace cgview::server {

// The gauges' values at a scrape.
struct MetricsSnapshot {
  std::map<std::pair<std::string, std::string>, std::size_t> jobs;  // (state, algorithm) -> jobs
  std::size_t queued = 0, running = 0;
  std::size_t meshes = 0;
  std::uint64_t store_bytes = 0;  // mesh files, textures and job artifacts
};

class Metrics {
 public:
  Metrics();
  ~Metrics();
  Metrics(const Metrics&) = delete;
  Metrics& operator=(const Metrics&) = delete;

  // A request answered: its route's pattern ("/api/v1/meshes/{id}"; "static"
  // for the web client's files, "unmatched" for no route: the label's values
  // stay few), method, HTTP status and seconds.
  void request(const std::string& route, const std::string& method, int status, double seconds);
  void websocket_opened();
  void websocket_closed();
  // A request or WebSocket message refused with 429.
  void rate_limited();
  // A job event (jobs/scheduler.h's on_event): a start begins the job's clock; done,
  // failed and cancelled count the end by algorithm and state, observe how
  // long it ran, and count a worker killed by a signal as a crash.
  void job_event(const nlohmann::json& event);
  // The text exposition (Content-Type: kContentType), gauges set from now.
  std::string text(const MetricsSnapshot& now);

  static constexpr const char* kContentType = "text/plain; version=0.0.4; charset=utf-8";

 private:
  std::shared_ptr<prometheus::Registry> registry_;
  prometheus::Family<prometheus::Counter>& requests_;
  prometheus::Family<prometheus::Histogram>& latency_;
  prometheus::Gauge& websockets_;
  prometheus::Counter& rate_limited_;
  prometheus::Family<prometheus::Counter>& jobs_ended_;
  prometheus::Family<prometheus::Histogram>& job_seconds_;
  prometheus::Counter& worker_crashes_;
  prometheus::Family<prometheus::Gauge>& jobs_;
  prometheus::Gauge& queued_;
  prometheus::Gauge& running_;
  prometheus::Gauge& meshes_;
  prometheus::Gauge& store_bytes_;
  std::mutex mutex_;
  std::map<std::string, std::chrono::steady_clock::time_point> started_;  // running jobs by id
  std::set<std::pair<std::string, std::string>> job_labels_;              // (state, algorithm) seen
};

}  // namespace cgview::server
