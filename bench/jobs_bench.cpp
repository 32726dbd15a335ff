// The job system's overhead: N tiny jobs (centroid_distance on a small
// mesh, each with another exponent so that the cache never answers)
// submitted over HTTP to the real cgview-server, completion seen through
// WebSocket job_done events.  Prints throughput, p50/p99 submit->done, and
// the per-job overhead against calling the algorithm in-process.
//
//   build/bin/jobs_bench [--jobs 1000] [--sequential 100] [--job-workers N] [--server build/bin/cgview-server] [--mesh
//   FILE]
#include <utility>  // before Boost 1.74's asio (std::exchange)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

#include "bench_server.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"

namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using nlohmann::json;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

using cgview::bench::ServerProcess;

namespace {

double ms(Clock::duration d) { return std::chrono::duration<double, std::milli>(d).count(); }

// One keep-alive HTTP connection.
class Http {
 public:
  explicit Http(unsigned short port) : socket_(ioc_) { socket_.connect({net::ip::address_v4::loopback(), port}); }
  http::response<http::string_body> call(http::verb method, const std::string& target, std::string body = "") {
    http::request<http::string_body> req{method, target, 11};
    req.set(http::field::host, "127.0.0.1");
    req.keep_alive(true);
    req.body() = std::move(body);
    req.prepare_payload();
    http::write(socket_, req);
    http::response_parser<http::string_body> parser;
    parser.body_limit(1u << 30);
    http::read(socket_, buffer_, parser);
    return parser.release();
  }

 private:
  net::io_context ioc_;
  tcp::socket socket_;
  beast::flat_buffer buffer_;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, std::size_t(p * double(v.size() - 1) + 0.5))];
}

}  // namespace

int main(int argc, char** argv) {
  int jobs = 1000, sequential = 100;
  std::string server = (fs::path(argv[0]).parent_path() / "cgview-server").string(), job_workers, sandbox;
  fs::path mesh_file;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--jobs" && i + 1 < argc) jobs = std::stoi(argv[++i]);
    else if (a == "--sequential" && i + 1 < argc) sequential = std::stoi(argv[++i]);
    else if (a == "--job-workers" && i + 1 < argc) job_workers = argv[++i];
    else if (a == "--server" && i + 1 < argc) server = argv[++i];
    else if (a == "--sandbox" && i + 1 < argc) sandbox = argv[++i];
    else if (a == "--mesh" && i + 1 < argc) mesh_file = argv[++i];
    else {
      std::fprintf(stderr,
                   "usage: jobs_bench [--jobs N] [--sequential N] [--job-workers N] [--sandbox on|off] [--server PATH] "
                   "[--mesh FILE]\n");
      return 2;
    }
  }
  if (mesh_file.empty())
    for (const auto& f : cgview::list_samples())
      if (f.filename() == "sphere.off") mesh_file = f;
  if (mesh_file.empty()) {
    std::fprintf(stderr, "jobs_bench: no sample sphere.off; pass --mesh FILE\n");
    return 2;
  }
  std::ifstream mf(mesh_file, std::ios::binary);
  std::stringstream mesh_bytes;
  mesh_bytes << mf.rdbuf();
  const cgview::Mesh mesh = cgview::read_mesh_file(mesh_file).mesh;

  // In-process: the algorithm alone, and with reading the mesh file.
  const auto& algo = cgview::find_algorithm("centroid_distance");
  cgview::Context ctx;
  const int direct_n = 2000;
  auto t0 = Clock::now();
  for (int i = 0; i < direct_n; ++i) algo.run(mesh, {{"exponent", 0.1 + 0.001 * i}}, ctx);
  const double direct_ms = ms(Clock::now() - t0) / direct_n;
  t0 = Clock::now();
  for (int i = 0; i < direct_n; ++i)
    algo.run(cgview::read_mesh_file(mesh_file).mesh, {{"exponent", 0.1 + 0.001 * i}}, ctx);
  const double direct_read_ms = ms(Clock::now() - t0) / direct_n;

  const fs::path data = fs::temp_directory_path() / ("cgview-jobs-bench-" + std::to_string(getpid()));
  fs::remove_all(data);
  int rc = 0;
  {
    std::vector<std::string> server_args;
    if (!job_workers.empty()) server_args.insert(server_args.end(), {"--job-workers", job_workers});
    if (!sandbox.empty()) server_args.insert(server_args.end(), {"--sandbox", sandbox});
    ServerProcess srv(server, data, server_args);
    Http client(srv.port);
    const std::string mesh_id = cgview::bench::upload(srv.port, mesh_file.filename().string(), mesh_bytes.str());

    // WebSocket: the time each job_done arrives.
    std::mutex m;
    std::condition_variable cv;
    std::map<std::string, Clock::time_point> done_at;
    std::map<std::string, std::string> failed;
    net::io_context ws_ioc;
    websocket::stream<tcp::socket> ws(ws_ioc);
    ws.next_layer().connect({net::ip::address_v4::loopback(), srv.port});
    ws.handshake("127.0.0.1", "/api/v1/ws");
    std::atomic<bool> stop{false};
    std::thread reader([&] {
      beast::flat_buffer buf;
      while (!stop) {
        beast::error_code ec;
        ws.read(buf, ec);
        if (ec) return;
        const auto now = Clock::now();
        const json e = json::parse(beast::buffers_to_string(buf.data()), nullptr, false);
        buf.consume(buf.size());
        const std::string type = e.value("type", "");
        if (type == "job_done" || type == "job_failed" || type == "job_cancelled") {
          std::lock_guard lock(m);
          done_at[e["job"]["id"]] = now;
          if (type != "job_done") failed[e["job"]["id"]] = e["job"].value("error", json()).dump();
          cv.notify_all();
        }
      }
    });
    int k = 0;
    auto submit = [&](std::vector<std::pair<std::string, Clock::time_point>>& out) {
      const double exponent = 0.1 + 3.8 * double(k++) / double(jobs + sequential);
      const json body = {
          {"algorithm", "centroid_distance"}, {"inputs", {{"mesh", mesh_id}}}, {"params", {{"exponent", exponent}}}};
      const auto t = Clock::now();
      const auto r = client.call(http::verb::post, "/api/v1/jobs", body.dump());
      if (r.result_int() != 201) throw std::runtime_error("submit failed: " + r.body());
      const json j = json::parse(r.body());
      if (j["cached"] == true) throw std::runtime_error("a job was answered from the cache");
      out.emplace_back(j["id"], t);
    };
    auto latencies = [&](const std::vector<std::pair<std::string, Clock::time_point>>& sub) {
      std::vector<double> lat;
      std::lock_guard lock(m);
      for (const auto& [id, t] : sub) lat.push_back(ms(done_at.at(id) - t));
      return lat;
    };
    auto wait_all = [&](const std::vector<std::pair<std::string, Clock::time_point>>& sub) {
      std::unique_lock lock(m);
      cv.wait(lock, [&] {
        for (const auto& [id, t] : sub)
          if (!done_at.count(id)) return false;
        return true;
      });
    };

    // (1) one at a time: the latency of a lone job.
    std::vector<std::pair<std::string, Clock::time_point>> seq;
    for (int i = 0; i < sequential; ++i) {
      submit(seq);
      wait_all(seq);
    }
    const auto seq_lat = latencies(seq);
    double seq_mean = 0;
    for (double v : seq_lat) seq_mean += v / double(seq_lat.size());

    // (2) a burst: every job submitted as fast as the client can.
    std::vector<std::pair<std::string, Clock::time_point>> burst;
    const auto b0 = Clock::now();
    for (int i = 0; i < jobs; ++i) submit(burst);
    const double submit_s = ms(Clock::now() - b0) / 1000;
    wait_all(burst);
    Clock::time_point last = b0;
    {
      std::lock_guard lock(m);
      for (const auto& [id, t] : burst) last = std::max(last, done_at.at(id));
    }
    const double total_s = ms(last - b0) / 1000;
    const auto lat = latencies(burst);
    stop = true;
    beast::error_code ec;
    ws.next_layer().shutdown(tcp::socket::shutdown_both, ec);
    ws.next_layer().close(ec);
    reader.join();
    if (!failed.empty()) {
      std::fprintf(stderr, "jobs_bench: %zu jobs did not complete, e.g. %s\n", failed.size(),
                   failed.begin()->second.c_str());
      rc = 1;
    }

    std::printf("## jobs_bench: %d jobs of centroid_distance on %s (%zu vertices), %s job workers, %u cores\n\n", jobs,
                mesh_file.filename().c_str(), mesh.num_vertices(),
                job_workers.empty() ? "default" : job_workers.c_str(), std::thread::hardware_concurrency());
    std::printf("| measure | value |\n|---|---:|\n");
    std::printf("| burst of %d jobs: submitted in | %.2f s |\n", jobs, submit_s);
    std::printf("| burst: first submit to last done | %.2f s |\n", total_s);
    std::printf("| throughput | %.0f jobs/s |\n", double(jobs) / total_s);
    std::printf("| burst submit->done p50 | %.1f ms |\n", percentile(lat, 0.5));
    std::printf("| burst submit->done p99 | %.1f ms |\n", percentile(lat, 0.99));
    std::printf("| lone job (%d, one at a time) submit->done mean | %.2f ms |\n", sequential, seq_mean);
    std::printf("| lone job submit->done p50 / p99 | %.2f / %.2f ms |\n", percentile(seq_lat, 0.5),
                percentile(seq_lat, 0.99));
    std::printf("| in-process algorithm call | %.4f ms |\n", direct_ms);
    std::printf("| in-process read mesh file + call | %.4f ms |\n", direct_read_ms);
    std::printf("| per-job overhead (lone job mean - in-process call) | %.2f ms |\n", seq_mean - direct_ms);
  }
  fs::remove_all(data);
  return rc;
}
