// Jobs against the real cgview-server with the test worker (cgview-worker-test):
// algorithms run in worker processes, artifacts in every format against an
// in-process run, bad requests, crashes, memory and time limits, cancellation,
// the result cache, WebSocket events and a server killed mid-job.
#include <gtest/gtest.h>

#include <utility>  // before Asio: Boost 1.74 uses std::exchange without it (GCC 12)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <cstring>
#include <vector>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "core/errors.h"

#include "io/mesh_io.h"
#include "store.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "test_support.h"

#include <sqlite3.h>

namespace cgview {
namespace {

namespace fs = std::filesystem;
namespace net = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = net::ip::tcp;
using nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

std::string read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// ---------------------------------------------------------------- the server

// One cgview-server child process; killed when this goes out of scope.
class ServerProcess {
 public:
  ServerProcess() = default;
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;
  ~ServerProcess() { kill_now(); }

  // Starts the binary and waits for its "CGView serving http://HOST:PORT/"
  // line; false (with a failure added) if it does not come.
  bool start(const fs::path& data_dir, const std::vector<std::string>& extra, const fs::path& log_dir) {
    kill_now();
    out_ = log_dir / ("stdout-" + std::to_string(++starts_) + ".txt");
    err_ = log_dir / ("stderr-" + std::to_string(starts_) + ".txt");
    std::vector<std::string> args = {test::bin("cgview-server"), "--host", "127.0.0.1", "--port", "0",
                                     "--data-dir", data_dir.string(), "--samples", "none"};
    args.insert(args.end(), extra.begin(), extra.end());
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t parent = ::getpid();
    pid_ = ::fork();
    if (pid_ < 0) {
      ADD_FAILURE() << "fork failed";
      return false;
    }
    if (pid_ == 0) {
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);  // never outlive the test
      if (::getppid() != parent) ::_exit(127);
      const int o = ::open(out_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(o, 1);
      ::dup2(e, 2);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    const std::regex line_re(R"(CGView serving http://([^/:]+):([0-9]+)/)");
    const auto deadline = Clock::now() + 30s;
    while (Clock::now() < deadline) {
      std::smatch m;
      const std::string out = read_bytes(out_);
      if (std::regex_search(out, m, line_re)) {
        port_ = static_cast<unsigned short>(std::stoi(m[2]));
        return port_ != 0;
      }
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        ADD_FAILURE() << "cgview-server exited at start (status " << status << "); stderr:\n" << read_bytes(err_);
        return false;
      }
      std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << "cgview-server printed no 'CGView serving' line in 30 s; stdout:\n"
                  << read_bytes(out_) << "\nstderr:\n" << read_bytes(err_);
    kill_now();
    return false;
  }

  // Sends a signal and waits for the exit; the exit status, or -1 (killed
  // after the time limit).
  int stop(int sig, std::chrono::milliseconds limit = 10s) {
    if (pid_ <= 0) return -1;
    ::kill(pid_, sig);
    const auto deadline = Clock::now() + limit;
    while (Clock::now() < deadline) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) {
        pid_ = -1;
        return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      }
      std::this_thread::sleep_for(10ms);
    }
    kill_now();
    return -1;
  }

  void kill_now() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      ::waitpid(pid_, nullptr, 0);
      pid_ = -1;
    }
  }

  bool alive() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return false;
    }
    return true;
  }

  // Resident memory in kB (VmRSS), or -1.
  long rss_kb() const {
    std::ifstream f("/proc/" + std::to_string(pid_) + "/status");
    for (std::string line; std::getline(f, line);)
      if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
    return -1;
  }

  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }
  std::string stderr_text() const { return read_bytes(err_); }

 private:
  pid_t pid_ = -1;
  unsigned short port_ = 0;
  int starts_ = 0;
  fs::path out_, err_;
};

// ---------------------------------------------------------------- clients

// Runs the context until done() or the time limit; false on the limit (or
// when nothing is left to run and done() is still false).
bool run_until(net::io_context& ioc, const std::function<bool()>& done, std::chrono::milliseconds limit) {
  const auto deadline = Clock::now() + limit;
  while (!done()) {
    ioc.restart();
    if (ioc.run_one_until(deadline) == 0) return done();
  }
  return true;
}

tcp::endpoint local(unsigned short port) { return {net::ip::address_v4::loopback(), port}; }

using Response = http::response<http::string_body>;

struct HttpResult {
  beast::error_code ec;  // of the read; set when no response came
  Response res;
  json body_json() const { return json::parse(res.body(), nullptr, false); }
};

// One request on its own connection (Connection: close).  The body is
// written while the response is read, as a client must to see an early
// answer (413) to a large upload.
HttpResult http_call(unsigned short port, http::verb method, const std::string& target, std::string body = "",
                     std::chrono::milliseconds limit = 30s) {
  HttpResult out;
  net::io_context ioc;
  tcp::socket socket(ioc);
  std::optional<beast::error_code> connected, wrote, read;
  socket.async_connect(local(port), [&](beast::error_code ec) { connected = ec; });
  if (!run_until(ioc, [&] { return connected.has_value(); }, limit) || *connected) {
    out.ec = connected.value_or(net::error::timed_out);
    return out;
  }
  http::request<http::string_body> req{method, target, 11};
  req.set(http::field::host, "127.0.0.1");
  req.set(http::field::user_agent, "cgview-test");
  req.keep_alive(false);
  req.body() = std::move(body);
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(std::numeric_limits<std::uint64_t>::max());
  parser.skip(method == http::verb::head);  // a HEAD response has no body, whatever its Content-Length
  http::async_write(socket, req, [&](beast::error_code ec, std::size_t) { wrote = ec; });
  http::async_read(socket, buffer, parser, [&](beast::error_code ec, std::size_t) { read = ec; });
  const bool done = run_until(ioc, [&] { return read.has_value(); }, limit);
  beast::error_code ignored;
  socket.close(ignored);

  run_until(ioc, [&] { return wrote.has_value() && read.has_value(); }, 5s);
  out.ec = done ? *read : beast::error_code(net::error::timed_out);
  if (!out.ec) out.res = parser.release();
  return out;
}

HttpResult http_get(unsigned short port, const std::string& target) { return http_call(port, http::verb::get, target); }

// A WebSocket client on its own io_context, every operation bounded in time.
class WsClient {
 public:
  WsClient() : ws_(ioc_) {}

  beast::error_code connect(unsigned short port, const std::string& target = "/api/v1/ws") {
    beast::error_code ec = op([&](auto h) { ws_.next_layer().async_connect(local(port), h); });
    if (ec) return ec;
    ws_.next_layer().set_option(tcp::no_delay(true), ec);
    return op([&](auto h) { ws_.async_handshake("127.0.0.1:" + std::to_string(port), target, h); });
  }

  beast::error_code send(const json& j) {
    ws_.text(true);
    const std::string text = j.dump();
    return op([&](auto h) { ws_.async_write(net::buffer(text), h); });
  }
  beast::error_code send_text(const std::string& text) {
    ws_.text(true);
    return op([&](auto h) { ws_.async_write(net::buffer(text), h); });
  }
  beast::error_code send_binary(const std::string& bytes) {
    ws_.binary(true);
    return op([&](auto h) { ws_.async_write(net::buffer(bytes), h); });
  }

  struct Message {
    bool binary = false;
    std::string data;
  };
  // The next message; nullopt on an error (last_error() says which).
  std::optional<Message> read(std::chrono::milliseconds limit = 30s) {
    beast::flat_buffer buffer;
    last_ = op([&](auto h) { ws_.async_read(buffer, h); }, limit);
    if (last_) return std::nullopt;
    return Message{ws_.got_binary(), beast::buffers_to_string(buffer.data())};
  }
  // The next text message that is not an event (mesh_added, mesh_deleted),
  // parsed; events are kept in events().
  json reply(std::chrono::milliseconds limit = 30s) {
    for (;;) {
      const auto m = read(limit);
      if (!m) {
        ADD_FAILURE() << "no WebSocket reply: " << last_.message();
        return json();
      }
      if (m->binary) {
        ADD_FAILURE() << "a binary message where a text reply was expected";
        return json();
      }
      json j = json::parse(m->data, nullptr, false);
      if (j.is_object() && (j.value("type", "") == "mesh_added" || j.value("type", "") == "mesh_deleted")) {
        events_.push_back(j);
        continue;
      }
      return j;
    }
  }

  bool ping(std::uint64_t request_id) {
    if (send({{"type", "ping"}, {"request_id", request_id}})) return false;
    const json j = reply();
    return j == json{{"type", "pong"}, {"request_id", request_id}};
  }

  beast::error_code close() { return op([&](auto h) { ws_.async_close(websocket::close_code::normal, h); }, 10s); }
  // Drops the TCP connection with a reset, no close handshake.
  void abort() {
    beast::error_code ec;
    ws_.next_layer().set_option(net::socket_base::linger(true, 0), ec);
    ws_.next_layer().close(ec);
  }

  beast::error_code last_error() const { return last_; }
  std::vector<json>& events() { return events_; }

 private:
  template <class Start>
  beast::error_code op(Start start, std::chrono::milliseconds limit = 30s) {
    auto result = std::make_shared<std::optional<beast::error_code>>();
    start([result](beast::error_code ec, auto&&...) { *result = ec; });
    if (run_until(ioc_, [&] { return result->has_value(); }, limit)) return **result;
    beast::error_code ignored;
    ws_.next_layer().close(ignored);  // the pending operation ends with an error
    run_until(ioc_, [&] { return result->has_value(); }, 5s);
    return net::error::timed_out;
  }

  net::io_context ioc_;
  websocket::stream<tcp::socket> ws_;
  beast::error_code last_;
  std::vector<json> events_;
};

// ---------------------------------------------------------------- jobs

constexpr int kMemoryMb = 512;
constexpr int kTimeoutS = 3;

class JobsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("jobs-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    data_ = dir_ / "data";
    ASSERT_TRUE(start());
    const std::string bytes = read_bytes(test::sample("sphere.off"));
    const auto r = http_call(server_.port(), http::verb::post, "/api/v1/meshes?name=sphere.off", bytes);
    ASSERT_EQ(r.res.result_int(), 201) << r.res.body();
    mesh_id_ = r.body_json()["id"];
  }

  bool start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--worker", test::bin("cgview-worker-test"), "--job-workers", "2",
                                     "--job-timeout-s", std::to_string(kTimeoutS), "--job-memory-mb",
                                     std::to_string(kMemoryMb)};
    args.insert(args.end(), extra.begin(), extra.end());
    return server_.start(data_, args, dir_);
  }

  json submit(const std::string& algorithm, const json& params, int expect = 201) {
    const json body = {{"algorithm", algorithm}, {"inputs", {{"mesh", mesh_id_}}}, {"params", params}};
    const auto r = http_call(server_.port(), http::verb::post, "/api/v1/jobs", body.dump());
    EXPECT_EQ(r.res.result_int(), expect) << r.res.body();
    return r.body_json();
  }

  json get(const std::string& id) { return http_get(server_.port(), "/api/v1/jobs/" + id).body_json(); }

  // Polls until the job leaves queued/running (or the limit); the last Job.
  json wait_end(const std::string& id, std::chrono::milliseconds limit = 20s) {
    const auto deadline = Clock::now() + limit;
    json j;
    while (Clock::now() < deadline) {
      j = get(id);
      const std::string s = j.value("state", "");
      if (s != "queued" && s != "running") return j;
      std::this_thread::sleep_for(20ms);
    }
    ADD_FAILURE() << "job " << id << " did not end in time: " << j.dump();
    return j;
  }

  json wait_state(const std::string& id, const std::string& state, std::chrono::milliseconds limit = 10s) {
    const auto deadline = Clock::now() + limit;
    json j;
    while (Clock::now() < deadline) {
      j = get(id);
      if (j.value("state", "") == state) return j;
      std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << "job " << id << " never became " << state << ": " << j.dump();
    return j;
  }

  std::string artifact(const std::string& id, const std::string& name, const std::string& format) {
    const auto r = http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/" + name + "?format=" + format);
    EXPECT_EQ(r.res.result_int(), 200) << format << ": " << r.res.body();
    return r.res.body();
  }

  // How many processes run a job of this id (its job.json on the command line).
  static int worker_processes(const std::string& job_id) {
    int n = 0;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string cmd = read_bytes(e.path() / "cmdline");
      if (cmd.find("cgview-worker") != std::string::npos && cmd.find(job_id) != std::string::npos) ++n;
    }
    return n;
  }

  fs::path dir_, data_;
  ServerProcess server_;
  std::string mesh_id_;
};

TEST_F(JobsTest, ListsAlgorithmsWithoutTheTestOnes) {
  const json list = http_get(server_.port(), "/api/v1/algorithms").body_json();
  bool centroid = false;
  for (const auto& a : list["algorithms"]) {
    EXPECT_NE(a["area"], "test") << a["name"];
    centroid |= a["name"] == "centroid_distance";
  }
  EXPECT_TRUE(centroid) << list.dump();
}

TEST_F(JobsTest, CentroidDistanceArtifactsMatchAnInProcessRun) {
  const json job = submit("centroid_distance", {{"exponent", 2}});
  EXPECT_EQ(job["state"], "queued");
  EXPECT_EQ(job["cached"], false);
  const json done = wait_end(job["id"]);
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["progress"], 1.0);
  ASSERT_EQ(done["artifacts"].size(), 1u);
  EXPECT_EQ(done["artifacts"][0]["name"], "distance");
  EXPECT_EQ(done["artifacts"][0]["kind"], "scalar_field");
  EXPECT_EQ(done["artifacts"][0]["location"], "vertex");
  EXPECT_EQ(done["params"], (json{{"exponent", 2.0}, {"normalize", false}}));

  // The same computation in-process.
  const Mesh mesh = read_mesh_file(test::sample("sphere.off")).mesh;
  Context ctx;
  const AlgorithmResult direct = find_algorithm("centroid_distance").run(mesh, {{"exponent", 2.0}}, ctx);
  const auto& field = std::get<ScalarField>(direct.artifacts.at(0).value);

  const std::string id = done["id"];
  const std::string f32 = artifact(id, "distance", "f32");
  ASSERT_EQ(f32.size(), field.values.size() * 4);
  EXPECT_EQ(0, std::memcmp(f32.data(), field.values.data(), f32.size()));

  const json j = json::parse(artifact(id, "distance", "json"));
  EXPECT_EQ(j["location"], "vertex");
  EXPECT_EQ(j["hint"], "magnitude");
  ASSERT_EQ(j["values"].size(), field.values.size());
  for (std::size_t i = 0; i < field.values.size(); ++i) EXPECT_EQ(j["values"][i].get<float>(), field.values[i]) << i;
  EXPECT_EQ(j["range"][0].get<float>(), field.range().first);
  EXPECT_EQ(j["range"][1].get<float>(), field.range().second);

  for (const std::string format : {"txt", "csv", "ply"}) {
    const fs::path p = dir_ / ("direct." + format);
    write_artifact(direct.artifacts[0], mesh, p);
    EXPECT_EQ(artifact(id, "distance", format), read_bytes(p)) << format;
  }
  // A format a field has not: 400; no such artifact: 404.
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/distance?format=obj").res.result_int(), 400);
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/nope").res.result_int(), 404);

  // The same job again: answered from the cache, no worker run.
  const json again = submit("centroid_distance", {{"exponent", 2.0}, {"normalize", false}});
  EXPECT_EQ(again["state"], "done");
  EXPECT_EQ(again["cached"], true);
  EXPECT_NE(again["id"], id);
  EXPECT_FALSE(fs::exists(data_ / "jobs" / again["id"].get<std::string>())) << "a worker ran for a cached job";
  EXPECT_EQ(artifact(again["id"], "distance", "f32"), f32);
  // Other parameters are another job.
  EXPECT_EQ(submit("centroid_distance", {{"exponent", 3}})["cached"], false);
  // Listed.
  const json list = http_get(server_.port(), "/api/v1/jobs").body_json();
  EXPECT_GE(list["jobs"].size(), 3u);
}

TEST_F(JobsTest, BadRequests) {
  json e = submit("centroid_distance", {{"exponent", 9}}, 400);
  EXPECT_EQ(e["error"], "bad_request");
  EXPECT_EQ(e["detail"], "parameter 'exponent': 9 is over the maximum 4");
  e = submit("centroid_distance", {{"rays", 9}}, 400);
  EXPECT_NE(e["detail"].get<std::string>().find("'rays'"), std::string::npos) << e.dump();
  e = submit("centroid_distance", {{"normalize", "yes"}}, 400);
  EXPECT_NE(e["detail"].get<std::string>().find("'normalize'"), std::string::npos) << e.dump();
  e = submit("no_such_algorithm", json::object(), 404);
  EXPECT_EQ(e["error"], "not_found");
  const auto r = http_call(server_.port(), http::verb::post, "/api/v1/jobs",
                           json{{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", "0000000000000000"}}}}.dump());
  EXPECT_EQ(r.res.result_int(), 404);
  EXPECT_EQ(http_call(server_.port(), http::verb::post, "/api/v1/jobs", "not json").res.result_int(), 400);
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/0000000000000000").res.result_int(), 404);
  EXPECT_EQ(http_call(server_.port(), http::verb::delete_, "/api/v1/jobs/0000000000000000").res.result_int(), 404);
}

TEST_F(JobsTest, CrashMemoryAndTimeLimitsFailAlone) {
  const json crash = submit("test_segfault", json::object());
  const json hog = submit("test_memory_hog", json::object());
  const json slow = submit("test_sleep", {{"seconds", 60}});
  const json c = wait_end(crash["id"]);
  EXPECT_EQ(c["state"], "failed");
  EXPECT_EQ(c["error"], "killed by signal SIGSEGV");
  const json h = wait_end(hog["id"]);
  EXPECT_EQ(h["state"], "failed");
  EXPECT_EQ(h["error"], "exceeded its memory limit of " + std::to_string(kMemoryMb) + " MB");
  const json s = wait_end(slow["id"]);
  EXPECT_EQ(s["state"], "failed");
  EXPECT_EQ(s["error"], "exceeded its time limit of " + std::to_string(kTimeoutS) + " s");
  EXPECT_NE(s["finished"], nullptr);
  // The server still answers, and another job still completes.
  EXPECT_EQ(http_get(server_.port(), "/api/v1/health").res.result_int(), 200);
  EXPECT_EQ(wait_end(submit("centroid_distance", {{"exponent", 1.5}})["id"])["state"], "done");
  EXPECT_TRUE(server_.alive());
}

TEST_F(JobsTest, CancelARunningJobWithinTwoSeconds) {
  const json job = submit("test_sleep", {{"seconds", 60}});
  const std::string id = job["id"];
  wait_state(id, "running");
  std::this_thread::sleep_for(200ms);
  const auto t0 = Clock::now();
  const auto r = http_call(server_.port(), http::verb::delete_, "/api/v1/jobs/" + id);
  ASSERT_EQ(r.res.result_int(), 200) << r.res.body();
  EXPECT_EQ(r.body_json()["state"], "cancelled");
  while (worker_processes(id) > 0 && Clock::now() - t0 < 3s) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(worker_processes(id), 0);
  EXPECT_LT(Clock::now() - t0, 2s);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(get(id)["state"], "cancelled");
  // A queued job cancels too (both workers busy).
  const json a = submit("test_sleep", {{"seconds", 60}}), b = submit("test_sleep", {{"seconds", 61}}),
             queued = submit("test_sleep", {{"seconds", 62}});
  EXPECT_EQ(http_call(server_.port(), http::verb::delete_, "/api/v1/jobs/" + queued["id"].get<std::string>()).body_json()["state"],
            "cancelled");
  http_call(server_.port(), http::verb::delete_, "/api/v1/jobs/" + a["id"].get<std::string>());
  http_call(server_.port(), http::verb::delete_, "/api/v1/jobs/" + b["id"].get<std::string>());
}

TEST_F(JobsTest, WebSocketEvents) {
  WsClient ws;
  ASSERT_FALSE(ws.connect(server_.port()));
  const json job = submit("test_sleep", {{"seconds", 0.6}});
  bool progress = false, done = false;
  const auto deadline = Clock::now() + 10s;
  while (!done && Clock::now() < deadline) {
    const auto m = ws.read(10s);
    ASSERT_TRUE(m);
    const json e = json::parse(m->data);
    if (e["type"] == "job_progress" && e["job"]["id"] == job["id"]) progress = true;
    if (e["type"] == "job_done" && e["job"]["id"] == job["id"]) {
      done = true;
      EXPECT_EQ(e["job"]["state"], "done");
      EXPECT_EQ(e["job"]["artifacts"].size(), 1u);
    }
  }
  EXPECT_TRUE(progress);
  EXPECT_TRUE(done);
  const json f = submit("test_segfault", json::object());
  for (;;) {
    const auto m = ws.read(10s);
    ASSERT_TRUE(m);
    const json e = json::parse(m->data);
    if (e["type"] == "job_failed") {
      EXPECT_EQ(e["job"]["id"], f["id"]);
      break;
    }
  }
}

std::string integrity_check(const fs::path& db_path) {
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(db_path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) return "cannot open";
  std::string result;
  sqlite3_exec(
      db, "PRAGMA integrity_check",
      [](void* out, int, char** values, char**) {
        *static_cast<std::string*>(out) += values[0] ? values[0] : "";
        return 0;
      },
      &result, nullptr);
  sqlite3_close(db);
  return result;
}

TEST_F(JobsTest, ServerKilledMidJobRunsItAgainAfterRestart) {
  const json finished = submit("centroid_distance", {{"exponent", 0.5}});
  ASSERT_EQ(wait_end(finished["id"])["state"], "done");
  const std::string f32 = artifact(finished["id"], "distance", "f32");
  const json slow = submit("test_sleep", {{"seconds", 1.5}});
  wait_state(slow["id"], "running");
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(worker_processes(slow["id"]), 0) << "the worker outlived its server";
  EXPECT_EQ(integrity_check(data_ / "cgview.db"), "ok");

  ASSERT_TRUE(start());
  EXPECT_EQ(get(finished["id"])["state"], "done");
  EXPECT_EQ(artifact(finished["id"], "distance", "f32"), f32);
  const json again = wait_end(slow["id"]);
  EXPECT_EQ(again["state"], "done") << again.dump();
  EXPECT_EQ(again["artifacts"].size(), 1u);

  // With --on-restart interrupt, a job the server was running is marked interrupted.
  const json slow2 = submit("test_sleep", {{"seconds", 30}});
  wait_state(slow2["id"], "running");
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  ASSERT_TRUE(start({"--on-restart", "interrupt"}));
  const json j = get(slow2["id"]);
  EXPECT_EQ(j["state"], "interrupted");
  EXPECT_NE(j["error"], nullptr);
  EXPECT_EQ(get(finished["id"])["state"], "done");
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  EXPECT_EQ(integrity_check(data_ / "cgview.db"), "ok");
}

}  // namespace
}  // namespace cgview
