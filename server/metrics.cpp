#include "metrics.h"

#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>
#include <prometheus/text_serializer.h>

#include <nlohmann/json.hpp>

namespace cgview::server {

namespace {
using prometheus::BuildCounter;
using prometheus::BuildGauge;
using prometheus::BuildHistogram;

// Requests: from a cached lookup (0.1 ms) to a large upload or encoding (tens of s).
const prometheus::Histogram::BucketBoundaries kRequestBuckets = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1,
                                                                 0.25,   0.5,   1,      2.5,   5,    10,    30};
// Jobs: from a cached or tiny job (a tenth of a second) to the hour-long limit.
const prometheus::Histogram::BucketBoundaries kJobBuckets = {0.1, 0.25, 0.5, 1,   2.5, 5,    10,
                                                             30,  60,   120, 300, 600, 1800, 3600};
}  // namespace

Metrics::Metrics()
    : registry_(std::make_shared<prometheus::Registry>()),
      requests_(BuildCounter()
                    .Name("cgview_http_requests_total")
                    .Help("HTTP requests answered, by route, method and status")
                    .Register(*registry_)),
      latency_(BuildHistogram()
                   .Name("cgview_http_request_duration_seconds")
                   .Help("Time to answer an HTTP request, by route")
                   .Register(*registry_)),
      websockets_(BuildGauge()
                      .Name("cgview_websocket_connections")
                      .Help("WebSocket connections open")
                      .Register(*registry_)
                      .Add({})),
      rate_limited_(BuildCounter()
                        .Name("cgview_rate_limited_total")
                        .Help("Requests and WebSocket messages refused with 429")
                        .Register(*registry_)
                        .Add({})),
      jobs_ended_(BuildCounter()
                      .Name("cgview_jobs_ended_total")
                      .Help("Jobs that ended, by algorithm and state (done, failed, cancelled)")
                      .Register(*registry_)),
      job_seconds_(BuildHistogram()
                       .Name("cgview_job_duration_seconds")
                       .Help("How long a job's worker ran, by algorithm")
                       .Register(*registry_)),
      worker_crashes_(BuildCounter()
                          .Name("cgview_worker_crashes_total")
                          .Help("Job workers killed by a signal (a crash, or over a limit)")
                          .Register(*registry_)
                          .Add({})),
      jobs_(BuildGauge()
                .Name("cgview_jobs")
                .Help("Jobs known to the server, by state and algorithm")
                .Register(*registry_)),
      queued_(
          BuildGauge().Name("cgview_job_queue_length").Help("Jobs waiting for a worker").Register(*registry_).Add({})),
      running_(BuildGauge().Name("cgview_jobs_running").Help("Jobs whose worker runs").Register(*registry_).Add({})),
      meshes_(BuildGauge().Name("cgview_meshes").Help("Meshes stored").Register(*registry_).Add({})),
      store_bytes_(BuildGauge()
                       .Name("cgview_store_bytes")
                       .Help("Bytes stored: mesh files, textures and job artifacts")
                       .Register(*registry_)
                       .Add({})) {}

Metrics::~Metrics() = default;

void Metrics::request(const std::string& route, const std::string& method, int status, double seconds) {
  requests_.Add({{"route", route}, {"method", method}, {"status", std::to_string(status)}}).Increment();
  latency_.Add({{"route", route}}, kRequestBuckets).Observe(seconds);
}

void Metrics::websocket_opened() { websockets_.Increment(); }
void Metrics::websocket_closed() { websockets_.Decrement(); }
void Metrics::rate_limited() { rate_limited_.Increment(); }

void Metrics::job_event(const nlohmann::json& e) {
  const std::string type = e.value("type", "");
  const nlohmann::json& job = e.contains("job") && e["job"].is_object() ? e["job"] : nlohmann::json::object();
  const std::string id = job.value("id", "");
  const auto now = std::chrono::steady_clock::now();
  if (type == "job_progress") {
    if (job.value("state", "") == "running" && job.value("stage", "") == "starting") {
      std::lock_guard lock(mutex_);
      started_[id] = now;
    }
    return;
  }
  if (type != "job_done" && type != "job_failed" && type != "job_cancelled") return;
  const std::string algorithm = job.value("algorithm", "");
  const std::string state = type.substr(4);  // done, failed, cancelled
  jobs_ended_.Add({{"algorithm", algorithm}, {"state", state}}).Increment();
  const nlohmann::json error = job.value("error", nlohmann::json());
  if (error.is_string() && error.get<std::string>().starts_with("killed by signal")) worker_crashes_.Increment();
  std::lock_guard lock(mutex_);
  if (const auto it = started_.find(id); it != started_.end()) {
    job_seconds_.Add({{"algorithm", algorithm}}, kJobBuckets)
        .Observe(std::chrono::duration<double>(now - it->second).count());
    started_.erase(it);
  }
}

std::string Metrics::text(const MetricsSnapshot& now) {
  {
    std::lock_guard lock(mutex_);
    // A state no job is in any more reads 0, not its last count.
    for (const auto& key : job_labels_) jobs_.Add({{"state", key.first}, {"algorithm", key.second}}).Set(0);
    for (const auto& [key, n] : now.jobs) {
      jobs_.Add({{"state", key.first}, {"algorithm", key.second}}).Set(double(n));
      job_labels_.insert(key);
    }
  }
  queued_.Set(double(now.queued));
  running_.Set(double(now.running));
  meshes_.Set(double(now.meshes));
  store_bytes_.Set(double(now.store_bytes));
  return prometheus::TextSerializer().Serialize(registry_->Collect());
}

}  // namespace cgview::server
