// GET /metrics on the real server, read back by the Prometheus project's own
// Python parser (Debian's python3-prometheus-client): after an upload, a
// finished job, a refused request and an open WebSocket, the counters,
// histograms and gauges say so; off loopback the route needs a token.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "server_harness.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

// Every sample of the exposition, parsed by prometheus_client: a list of
// {"name", "labels", "value"}.
json parse_exposition(const fs::path& dir, const std::string& text) {
  write_text(dir / "metrics.txt", text);
  write_text(dir / "parse.py",
             "import json, sys\n"
             "from prometheus_client.parser import text_string_to_metric_families\n"
             "out = [{'name': s.name, 'labels': s.labels, 'value': s.value}\n"
             "       for f in text_string_to_metric_families(open(sys.argv[1]).read()) for s in f.samples]\n"
             "print(json.dumps(out))\n");
  std::string out;
  const int rc = run("/usr/bin/python3 " + (dir / "parse.py").string() + " " + (dir / "metrics.txt").string(), &out);
  EXPECT_EQ(rc, 0) << "prometheus_client could not parse the exposition:\n" << out << "\n" << text;
  return json::parse(out, nullptr, false);
}

// The value of the sample with this name and these labels (all of them), or -1.
double value_of(const json& samples, const std::string& name, const json& labels = json::object()) {
  for (const auto& s : samples)
    if (s["name"] == name && s["labels"] == labels) return s["value"].get<double>();
  return -1;
}

class MetricsTest : public ServerFixture {
 protected:
  MetricsTest() : ServerFixture("metrics-") {}
};

TEST_F(MetricsTest, RequestsJobsWebSocketsAndTheStoreAreCountedAsPrometheusReadsThem) {
  ASSERT_TRUE(server_.start(data_, {}, dir_));
  const std::string bytes = read_bytes(sample("elephant.off"));
  const HttpResult up = http_call(port(), Method::post, "/api/v1/meshes?name=elephant.off", bytes);
  ASSERT_EQ(up.status, 201u) << up.body;
  const std::string mesh = up.body_json()["id"];
  EXPECT_EQ(http_get(port(), "/api/v1/meshes/nope").status, 404u);
  EXPECT_EQ(http_get(port(), "/api/v1/no/such/route").status, 404u);
  const HttpResult sub = http_call(port(), Method::post, "/api/v1/jobs",
                                   json{{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", mesh}}}}.dump());
  ASSERT_EQ(sub.status, 201u) << sub.body;
  const std::string job = sub.body_json()["id"];
  for (int i = 0; i < 500 && http_get(port(), "/api/v1/jobs/" + job).body_json().value("state", "") != "done"; ++i)
    std::this_thread::sleep_for(20ms);
  WsClient ws;
  ASSERT_FALSE(ws.connect(port()));
  ASSERT_TRUE(ws.ping(1));

  // A job's end reaches the metrics as its event, just after its state is
  // saved: a client may see "done" a moment before the counter moves.
  for (int i = 0; i < 250; ++i) {
    const json now = parse_exposition(dir_, http_get(port(), "/metrics").body);
    if (value_of(now, "cgview_jobs_ended_total", {{"algorithm", "centroid_distance"}, {"state", "done"}}) == 1) break;
    std::this_thread::sleep_for(20ms);
  }
  const HttpResult m = http_get(port(), "/metrics");
  ASSERT_EQ(m.status, 200u) << m.body;
  EXPECT_EQ(m.header("Content-Type"), "text/plain; version=0.0.4; charset=utf-8");
  const json s = parse_exposition(dir_, m.body);
  ASSERT_TRUE(s.is_array());
  // prometheus_client names a counter's sample NAME_total.
  EXPECT_EQ(
      value_of(s, "cgview_http_requests_total", {{"route", "/api/v1/meshes"}, {"method", "POST"}, {"status", "201"}}),
      1);
  EXPECT_EQ(value_of(s, "cgview_http_requests_total",
                     {{"route", "/api/v1/meshes/{id}"}, {"method", "GET"}, {"status", "404"}}),
            1);
  EXPECT_EQ(value_of(s, "cgview_http_requests_total", {{"route", "unmatched"}, {"method", "GET"}, {"status", "404"}}),
            1);
  EXPECT_EQ(value_of(s, "cgview_http_request_duration_seconds_count", {{"route", "/api/v1/meshes"}}), 1);
  EXPECT_EQ(value_of(s, "cgview_http_request_duration_seconds_bucket", {{"route", "/api/v1/meshes"}, {"le", "+Inf"}}),
            1);
  EXPECT_GT(value_of(s, "cgview_http_request_duration_seconds_sum", {{"route", "/api/v1/meshes"}}), 0);
  EXPECT_EQ(value_of(s, "cgview_jobs_ended_total", {{"algorithm", "centroid_distance"}, {"state", "done"}}), 1);
  EXPECT_EQ(value_of(s, "cgview_job_duration_seconds_count", {{"algorithm", "centroid_distance"}}), 1);
  EXPECT_EQ(value_of(s, "cgview_jobs", {{"state", "done"}, {"algorithm", "centroid_distance"}}), 1);
  EXPECT_EQ(value_of(s, "cgview_job_queue_length"), 0);
  EXPECT_EQ(value_of(s, "cgview_jobs_running"), 0);
  EXPECT_EQ(value_of(s, "cgview_worker_crashes_total"), 0);
  EXPECT_EQ(value_of(s, "cgview_websocket_connections"), 1);
  EXPECT_EQ(value_of(s, "cgview_meshes"), 1);
  // The store: the mesh file, and the job's directory (its artifacts and log).
  std::uintmax_t job_bytes = 0;
  for (const auto& e : fs::recursive_directory_iterator(data_ / "jobs" / job))
    if (e.is_regular_file()) job_bytes += e.file_size();
  EXPECT_EQ(value_of(s, "cgview_store_bytes"), double(bytes.size() + job_bytes));

  ws.close();
  for (int i = 0; i < 100; ++i) {
    if (value_of(parse_exposition(dir_, http_get(port(), "/metrics").body), "cgview_websocket_connections") == 0) break;
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_EQ(value_of(parse_exposition(dir_, http_get(port(), "/metrics").body), "cgview_websocket_connections"), 0);
}

TEST_F(MetricsTest, OffLoopbackOrWithAuthRequiredTheMetricsNeedAToken) {
  fs::create_directories(data_);
  const std::string token = server_command(data_, "user add admin --admin");
  ASSERT_TRUE(server_.start(data_, {"--auth", "required"}, dir_));
  const HttpResult none = http_get(port(), "/metrics");
  expect_error(none, 401, "unauthorized");
  const HttpResult ok = call_as(port(), token, "GET", "/metrics");
  EXPECT_EQ(ok.status, 200u) << ok.body;
  EXPECT_NE(ok.body.find("# TYPE cgview_http_requests_total counter"), std::string::npos) << ok.body;
}

}  // namespace
}  // namespace cgview::test
