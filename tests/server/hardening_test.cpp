// The server's limits on the real cgview-server (docs/DEPLOYMENT.md, "Limits
// and hardening"), with timeouts of a second or two: a client sending one
// byte a second is cut off (408) while others are served, idle connections
// are closed, oversized headers (431), bodies (413) and WebSocket messages
// end only their connection, the per-address connection cap (503), the
// per-token rate limit (429, then served again), ids that try to be paths
// (every route, through the router), and TLS (https and wss with a
// self-signed certificate; plain HTTP on the TLS port is refused).  After
// each, the server still serves.
#include <gtest/gtest.h>

#include <utility>  // Boost 1.74's asio/awaitable.hpp uses std::exchange without it

#include <boost/asio.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/ssl.hpp>
#include <boost/beast/websocket.hpp>
#include <boost/beast/websocket/ssl.hpp>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include "mesh_service.h"
#include "rate_limit.h"
#include "router.h"
#include "server_harness.h"
#include "store.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// ---------------------------------------------------------------- raw sockets

// A plain TCP connection to the server, for clients that misbehave on purpose.
class RawSocket {
 public:
  explicit RawSocket(unsigned short port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd_);
      fd_ = -1;
    }
  }
  ~RawSocket() {
    if (fd_ >= 0) ::close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  bool send(const std::string& s) { return ::send(fd_, s.data(), s.size(), MSG_NOSIGNAL) == ssize_t(s.size()); }
  // Whether the server has sent something or closed, within `wait`.
  bool readable(std::chrono::milliseconds wait) {
    pollfd p{fd_, POLLIN, 0};
    return ::poll(&p, 1, int(wait.count())) > 0;
  }
  // Everything until the server closes (eof set) or `limit` passes.
  std::string read_all(std::chrono::milliseconds limit, bool* eof = nullptr) {
    std::string out;
    const auto until = Clock::now() + limit;
    if (eof) *eof = false;
    while (Clock::now() < until) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now());
      if (!readable(std::max(left, 1ms))) continue;
      char buf[4096];
      const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
      if (n <= 0) {  // closed (or reset)
        if (eof) *eof = true;
        break;
      }
      out.append(buf, std::size_t(n));
    }
    return out;
  }

 private:
  int fd_ = -1;
};

// "HTTP/1.1 408 ..." -> 408, and the JSON body after the headers.
unsigned status_of(const std::string& response) {
  std::smatch m;
  return std::regex_search(response, m, std::regex(R"(^HTTP/1\.1 ([0-9]{3}) )")) ? unsigned(std::stoi(m[1])) : 0;
}
json body_of(const std::string& response) {
  const std::size_t p = response.find("\r\n\r\n");
  return p == std::string::npos ? json() : json::parse(response.substr(p + 4), nullptr, false);
}

// ---------------------------------------------------------------- fixture

class Hardening : public test::ServerFixture {
 protected:
  Hardening() : ServerFixture("hardening-") {}
  void SetUp() override {
    ServerFixture::SetUp();
    fs::create_directories(data_);
  }
  bool start(const std::vector<std::string>& extra) { return server_.start(data_, extra, dir_); }

  // A new user's token (cgview-server user add, before the server starts).
  std::string add_user(const std::string& name) {
    const std::string out = server_command(data_, "user add " + name);
    std::smatch m;
    EXPECT_TRUE(std::regex_search(out, m, std::regex("cgv_[0-9a-f]{16}_[0-9a-f]{64}"))) << out;
    return m.empty() ? "" : m.str();
  }
};

// ---------------------------------------------------------------- slow and idle clients

TEST_F(Hardening, AClientSendingOneByteASecondIsCutOffWhileOthersAreServed) {
  ASSERT_TRUE(start({"--request-timeout-s", "2"}));
  const std::string request = "GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
  RawSocket slow(port());
  ASSERT_TRUE(slow.ok());
  std::atomic<int> served{0};
  std::thread others([&] {  // normal clients, all the while
    for (auto until = Clock::now() + 3s; Clock::now() < until; std::this_thread::sleep_for(50ms))
      if (http_get(port(), "/api/v1/health").status == 200) ++served;
  });
  const auto t0 = Clock::now();
  std::size_t sent = 0;
  std::string answer;
  bool eof = false;
  while (sent < request.size() && since(t0) < 10) {
    if (!slow.send(request.substr(sent, 1))) break;  // the server has closed
    ++sent;
    if (slow.readable(1000ms)) {
      answer = slow.read_all(3s, &eof);
      break;
    }
  }
  const double cut_after = since(t0);
  others.join();
  EXPECT_LT(sent, 5u) << "the slow client was not cut off";
  EXPECT_GE(cut_after, 1.8);
  EXPECT_LT(cut_after, 4.5);
  EXPECT_EQ(status_of(answer), 408u) << answer;
  EXPECT_EQ(body_of(answer).value("error", ""), "request_timeout") << answer;
  EXPECT_TRUE(eof) << "the connection stays open after the 408";
  EXPECT_GE(served.load(), 20) << "others were not served while the slow client was";
  expect_healthy();
}

TEST_F(Hardening, ABodyUnderTheMinimumRateIs408AndOneAboveItIsServed) {
  ASSERT_TRUE(start({"--request-timeout-s", "1", "--min-body-rate-kb", "64"}));
  {  // announces 1 MB and sends a byte a second
    RawSocket slow(port());
    ASSERT_TRUE(slow.ok());
    ASSERT_TRUE(
        slow.send("POST /api/v1/meshes?name=x.off HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: 1000000\r\n\r\n"));
    const auto t0 = Clock::now();
    std::string answer;
    for (int i = 0; i < 10 && answer.empty(); ++i) {
      slow.send("O");
      if (slow.readable(1000ms)) answer = slow.read_all(3s);
    }
    EXPECT_LT(since(t0), 3.5);
    EXPECT_EQ(status_of(answer), 408u) << answer;
    EXPECT_EQ(body_of(answer).value("error", ""), "request_timeout") << answer;
  }
  // 300 KB at about 150 KB/s: twice the request timeout, but over the
  // minimum rate all along, so its deadline grows with it.
  const std::string mesh = test::read_bytes(test::sample("dino.off"));
  RawSocket upload(port());
  ASSERT_TRUE(upload.ok());
  ASSERT_TRUE(upload.send(
      "POST /api/v1/meshes?name=dino.off HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\nContent-Length: " +
      std::to_string(mesh.size()) + "\r\n\r\n"));
  const auto t0 = Clock::now();
  for (std::size_t at = 0; at < mesh.size(); at += 15000) {
    ASSERT_TRUE(upload.send(mesh.substr(at, 15000))) << "cut off after " << at << " bytes";
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_GT(since(t0), 1.5);
  const std::string answer = upload.read_all(30s);
  EXPECT_EQ(status_of(answer), 201u) << answer.substr(0, 400);
  expect_healthy();
}

TEST_F(Hardening, IdleConnectionsAreClosed) {
  ASSERT_TRUE(start({"--idle-timeout-s", "1", "--ws-idle-timeout-s", "2"}));
  {  // no request at all
    RawSocket idle(port());
    ASSERT_TRUE(idle.ok());
    const auto t0 = Clock::now();
    bool eof = false;
    const std::string got = idle.read_all(5s, &eof);
    EXPECT_TRUE(eof);
    EXPECT_TRUE(got.empty()) << got;
    EXPECT_GE(since(t0), 0.8);
    EXPECT_LT(since(t0), 3.0);
  }
  {  // one request on a keep-alive connection, then nothing
    RawSocket idle(port());
    ASSERT_TRUE(idle.send("GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    const auto t0 = Clock::now();
    bool eof = false;
    const std::string got = idle.read_all(5s, &eof);
    EXPECT_EQ(status_of(got), 200u) << got;
    EXPECT_TRUE(eof);
    EXPECT_GE(since(t0), 0.8);
    EXPECT_LT(since(t0), 3.0);
  }
  {  // a WebSocket that never answers the server's pings
    RawSocket ws(port());
    ASSERT_TRUE(
        ws.send("GET /api/v1/ws HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n"));
    const auto t0 = Clock::now();
    bool eof = false;
    const std::string got = ws.read_all(8s, &eof);
    EXPECT_EQ(status_of(got), 101u) << got.substr(0, 200);
    EXPECT_NE(got.find("\x89"), std::string::npos) << "no ping came";  // a ping frame's first byte
    EXPECT_TRUE(eof);
    EXPECT_GE(since(t0), 1.5);
    EXPECT_LT(since(t0), 5.0);
  }
  expect_healthy();
}

// Where tokens are needed, a WebSocket that never authenticates is closed
// after --ws-auth-timeout-s, while one that did stays open.
TEST_F(Hardening, AWebSocketThatNeverAuthenticatesIsClosed) {
  fs::create_directories(data_);
  const std::string token = test::server_command(data_, "user add alice");
  ASSERT_TRUE(start({"--auth", "required", "--ws-auth-timeout-s", "1"}));
  test::WsClient silent, signed_in;
  ASSERT_FALSE(silent.connect(port()));
  ASSERT_FALSE(signed_in.connect(port()));
  ASSERT_FALSE(signed_in.send({{"type", "auth"}, {"token", token}, {"request_id", 1}}));
  EXPECT_EQ(signed_in.reply().value("type", ""), "authenticated");
  const auto t0 = Clock::now();
  EXPECT_FALSE(silent.read(5s).has_value()) << "the unauthenticated WebSocket stayed open";
  EXPECT_GE(since(t0), 0.5);
  EXPECT_LT(since(t0), 3.0);
  EXPECT_TRUE(signed_in.ping(2)) << "the authenticated one was closed too";
  EXPECT_EQ(call_as(port(), token, "GET", "/api/v1/health").status, 200u);
}

// ---------------------------------------------------------------- sizes

TEST_F(Hardening, OversizedHeadersBodiesAndWebSocketMessagesEndOnlyTheirConnection) {
  ASSERT_TRUE(start({"--max-header-kb", "4", "--max-upload-mb", "1", "--max-ws-message-kb", "64"}));
  WsClient bystander;
  ASSERT_FALSE(bystander.connect(port()));

  const HttpResult headers = http_raw(
      port(), "GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Pad: " + std::string(8000, 'x') + "\r\n\r\n");
  expect_error(headers, 431, "headers_too_large");
  EXPECT_FALSE(headers.keep_alive);
  // Just under the limit is served.
  EXPECT_EQ(http_raw(port(), "GET /api/v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Pad: " + std::string(3000, 'x') +
                                 "\r\nConnection: close\r\n\r\n")
                .status,
            200u);

  const HttpResult body = http_call(port(), Method::post, "/api/v1/meshes?name=big.off", std::string(2 << 20, ' '));
  expect_error(body, 413, "payload_too_large");
  EXPECT_FALSE(body.keep_alive);

  // The WebSocket is closed; an error message may come first (Beast
  // closes the stream as it reports the size, the client may be mid-send).
  WsClient big;
  ASSERT_FALSE(big.connect(port()));
  big.send_text(R"({"type":"ping","request_id":1,"pad":")" + std::string(100 << 10, 'x') + R"("})");
  bool closed = false;
  for (int i = 0; i < 3 && !closed; ++i) {
    const auto m = big.read(10s);
    if (!m) {
      closed = true;
      break;
    }
    const json j = json::parse(m->data, nullptr, false);
    EXPECT_EQ(j.value("error", ""), "payload_too_large") << m->data.substr(0, 200);
  }
  EXPECT_TRUE(closed) << "the connection stays open";
  EXPECT_TRUE(bystander.ping(2));
  expect_healthy();
}

TEST_F(Hardening, ConnectionsPerAddressAreCapped) {
  ASSERT_TRUE(start({"--max-connections-per-ip", "3"}));
  std::vector<std::unique_ptr<RawSocket>> held;
  for (int i = 0; i < 3; ++i) {
    held.push_back(std::make_unique<RawSocket>(port()));
    ASSERT_TRUE(held.back()->ok());
  }
  std::this_thread::sleep_for(200ms);  // the server has accepted them
  expect_error(http_get(port(), "/api/v1/health"), 503, "too_many_connections");
  held.pop_back();
  std::this_thread::sleep_for(300ms);  // the server has seen it close
  expect_healthy();
}

// Each connection is a file descriptor: a server started under a login's
// soft limit (here 64) takes its hard limit, and holds more connections than
// the soft limit allowed.
TEST_F(Hardening, TheServerTakesItsHardLimitOfOpenFiles) {
  rlimit mine{};
  ASSERT_EQ(getrlimit(RLIMIT_NOFILE, &mine), 0);
  if (mine.rlim_max < 1024) GTEST_SKIP() << "this machine's hard limit of open files is " << mine.rlim_max;
  rlimit low = mine;
  low.rlim_cur = 64;  // the server inherits it
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &low), 0);
  const bool started = start({});
  ASSERT_EQ(setrlimit(RLIMIT_NOFILE, &mine), 0);
  ASSERT_TRUE(started);
  rlimit server{};
  ASSERT_EQ(prlimit(server_.pid(), RLIMIT_NOFILE, nullptr, &server), 0);
  EXPECT_EQ(server.rlim_cur, mine.rlim_max);
  std::vector<std::unique_ptr<RawSocket>> held;
  for (int i = 0; i < 200; ++i) held.push_back(std::make_unique<RawSocket>(port()));
  // Each is accepted: a request on the last one is answered.
  ASSERT_TRUE(held.back()->send("GET /api/v1/health HTTP/1.1\r\nHost: x\r\n\r\n"));
  EXPECT_EQ(status_of(held.back()->read_all(2s)), 200u);
}

// Out of file descriptors, a connection waits in the backlog: the server
// waits for one to close instead of retrying the accept at once (a loop at
// a full core), says so once, and serves again when connections close.
TEST_F(Hardening, OutOfFileDescriptorsTheServerWaitsAndServesAgainOnceConnectionsClose) {
  ASSERT_TRUE(start({}));
  const auto open_now =
      std::distance(fs::directory_iterator("/proc/" + std::to_string(server_.pid()) + "/fd"), fs::directory_iterator{});
  const rlimit few{rlim_t(open_now + 10), rlim_t(open_now + 10)};
  ASSERT_EQ(prlimit(server_.pid(), RLIMIT_NOFILE, &few, nullptr), 0);
  std::vector<std::unique_ptr<RawSocket>> held;
  for (int i = 0; i < 30; ++i) held.push_back(std::make_unique<RawSocket>(port()));  // the kernel's backlog takes them
  std::this_thread::sleep_for(500ms);
  const auto cpu_s = [&] {
    std::ifstream f("/proc/" + std::to_string(server_.pid()) + "/stat");
    std::string text((std::istreambuf_iterator<char>(f)), {});
    std::istringstream rest(text.substr(text.rfind(')') + 2));
    std::string field;
    long ticks = 0;
    for (int i = 3; i <= 15 && rest >> field; ++i)
      if (i == 14 || i == 15) ticks += std::stol(field);  // utime, stime
    return double(ticks) / double(sysconf(_SC_CLK_TCK));
  };
  const double before = cpu_s();
  const auto t = Clock::now();
  std::this_thread::sleep_for(1500ms);
  EXPECT_LT((cpu_s() - before) / since(t), 0.5) << "the server spins while out of file descriptors";
  EXPECT_NE(server_.stderr_text().find("out of file descriptors"), std::string::npos) << server_.stderr_text();
  held.clear();
  std::this_thread::sleep_for(500ms);  // the server has seen them close
  expect_healthy();
}

// A job cancelled at once may get its SIGTERM before its worker has exec'ed,
// while the child is still a copy of the server with its signal handler: the
// server must not take it for its own.
TEST_F(Hardening, JobsCancelledAtOnceDoNotStopTheServer) {
  ASSERT_TRUE(start({"--job-workers", "2"}));
  const HttpResult up = http_call(port(), Method::post, "/api/v1/meshes?name=elephant.off",
                                  test::read_bytes(test::sample("elephant.off")));
  ASSERT_EQ(up.status, 201u) << up.body;
  const std::string mesh = up.body_json().value("id", "");
  for (int i = 0; i < 40; ++i) {
    const json request = {
        {"algorithm", "voxelize"}, {"inputs", {{"mesh", mesh}}}, {"params", {{"resolution", 900 + i}}}};
    const HttpResult job = http_call(port(), Method::post, "/api/v1/jobs", request.dump());
    ASSERT_EQ(job.status, 201u) << i << ": " << job.body << job.ec.message();
    const HttpResult cancel = http_call(port(), Method::delete_, "/api/v1/jobs/" + job.body_json().value("id", ""));
    ASSERT_EQ(cancel.status, 200u) << i << ": " << cancel.body << cancel.ec.message();
  }
  std::this_thread::sleep_for(300ms);
  EXPECT_TRUE(server_.alive());
  expect_healthy();
  // Nothing of theirs is left: bubblewrap cancelled while it set a sandbox
  // up left the sandbox's first process waiting for it forever.  (The
  // worker started for the next job waits, as it should.)
  for (const auto& [pid, cmdline] : test::processes_outliving(data_, 5s, test::kPrestartedWorker))
    ADD_FAILURE() << "outlived its cancelled job: " << pid << " " << cmdline.substr(0, 300);
}

// ---------------------------------------------------------------- rate limit

TEST(RateLimiter, ABucketOfBurstRefilledAtRate) {
  server::RateLimiter limit(2, 3);
  const auto t = server::RateLimiter::Clock::now();
  for (int i = 0; i < 3; ++i) EXPECT_FALSE(limit.take("a", t)) << i;
  const auto wait = limit.take("a", t);
  ASSERT_TRUE(wait);
  EXPECT_NEAR(*wait, 0.5, 1e-9);
  EXPECT_FALSE(limit.take("b", t)) << "another key has its own bucket";
  EXPECT_FALSE(limit.take("a", t + 500ms));
  EXPECT_TRUE(limit.take("a", t + 500ms));
  EXPECT_FALSE(limit.take("", t)) << "an empty key is not limited";
  server::RateLimiter none(0, 10);
  for (int i = 0; i < 100; ++i) EXPECT_FALSE(none.take("a", t));
}

TEST(RateLimiter, KeysAreTokenIdsOrAddresses) {
  const std::string token = "cgv_0123456789abcdef_" + std::string(64, '0');
  EXPECT_EQ(server::rate_key("Bearer " + token, "10.0.0.1", false), "token:0123456789abcdef");
  EXPECT_EQ(server::rate_key("bearer " + token, "127.0.0.1", true), "token:0123456789abcdef");
  EXPECT_EQ(server::rate_key("Bearer nonsense", "10.0.0.1", false), "ip:10.0.0.1");
  EXPECT_EQ(server::rate_key("", "10.0.0.1", false), "ip:10.0.0.1");
  EXPECT_EQ(server::rate_key("", "127.0.0.1", true), "") << "the loopback local user is not limited";
}

TEST_F(Hardening, OverTheRateLimitIs429ThenServedAfterRetryAfter) {
  const std::string alice = add_user("alice"), bob = add_user("bob");
  ASSERT_TRUE(start({"--rate-limit", "2/3", "--auth", "required"}));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(call_as(port(), alice, "GET", "/api/v1/health").status, 200u) << i;
  const HttpResult over = call_as(port(), alice, "GET", "/api/v1/health");
  expect_error(over, 429, "rate_limited");
  EXPECT_NE(over.body_json().value("detail", "").find("2 requests per second, bursts of 3"), std::string::npos)
      << over.body;
  const int retry = std::atoi(over.header("Retry-After").c_str());
  EXPECT_GE(retry, 1) << over.header("Retry-After");
  // Another token has its own bucket.
  EXPECT_EQ(call_as(port(), bob, "GET", "/api/v1/health").status, 200u);
  std::this_thread::sleep_for(std::chrono::seconds(retry) + 100ms);
  EXPECT_EQ(call_as(port(), alice, "GET", "/api/v1/health").status, 200u);

  // WebSocket messages count too, against the token of the session: of
  // six pings at once, the burst is served and the rest refused.
  WsClient ws;
  ASSERT_FALSE(ws.connect(port()));
  ASSERT_FALSE(ws.send({{"type", "auth"}, {"token", bob}, {"request_id", 1}}));
  EXPECT_EQ(ws.reply().value("type", ""), "authenticated");
  for (int i = 0; i < 6; ++i) ws.send({{"type", "ping"}, {"request_id", 10 + i}});
  int pongs = 0, refused = 0;
  for (int i = 0; i < 6; ++i) {
    const json r = ws.reply();
    if (r.value("type", "") == "pong") ++pongs;
    if (r.value("error", "") == "rate_limited") {
      ++refused;
      EXPECT_TRUE(r["retry_after_s"].is_number()) << r.dump();
    }
  }
  EXPECT_GE(pongs, 3);
  EXPECT_LE(pongs, 4);
  EXPECT_EQ(pongs + refused, 6);
  std::this_thread::sleep_for(1100ms);
  EXPECT_TRUE(ws.ping(4)) << "the session stays open and is served again";
}

// ---------------------------------------------------------------- ids are never paths

// Every route with a {parameter}: values that try to leave the data
// directory or to smuggle a NUL or a separator are 400 (one path segment) or
// 404/405 (a decoded '/' makes another path), never served, never a 500.
TEST(IdsAreNeverPaths, OverEveryRoute) {
  const fs::path dir = test::temp_dir("hardening-ids");
  test::write_text(dir / "secret.txt", "SECRET");
  server::Store store(dir / "data");
  server::MeshService meshes(store);
  server::Router router(meshes, {});
  const std::vector<std::string> one_segment = {
      "..", ".",       "%2e%2e", "%2E.", "a%00b", "%00", "..%5c..%5csecret.txt", "a%20b", "%2e%2e%5csecret.txt",
      "~",  "a%0d%0ab"};
  const std::vector<std::string> with_slash = {"%2e%2e%2fsecret.txt", "..%2F..%2Fsecret.txt", "%2fetc%2fpasswd",
                                               "..%2f..%2f..%2f..%2fetc%2fpasswd"};
  int checked = 0;
  for (const auto& r : router.routes()) {
    if (r.pattern.find('{') == std::string::npos) continue;
    for (int g = 0; g < 2; ++g)
      for (const std::string& bad : g == 0 ? one_segment : with_slash) {
        const std::string target = std::regex_replace(r.pattern, std::regex(R"(\{[a-z_]+\})"), bad);
        SCOPED_TRACE(r.method + " " + target);
        const server::HttpResponse res = router.handle({r.method, target, "{}", ""});
        if (g == 0) {
          EXPECT_EQ(res.status, 400) << res.body;
          EXPECT_EQ(json::parse(res.body, nullptr, false).value("error", ""), "bad_request") << res.body;
        } else {
          EXPECT_TRUE(res.status == 400 || res.status == 404 || res.status == 405) << res.status << " " << res.body;
        }
        EXPECT_EQ(res.body.find("SECRET"), std::string::npos);
        EXPECT_EQ(res.body.find("root:"), std::string::npos);
        ++checked;
      }
  }
  EXPECT_GE(checked, 10 * 15);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

// ---------------------------------------------------------------- TLS

namespace net = boost::asio;
namespace beast = boost::beast;
namespace ssl = net::ssl;
using tcp = net::ip::tcp;

// A TLS client that trusts only `ca`; its handshake fails on any other certificate.
struct TlsClient {
  explicit TlsClient(const fs::path& ca) : ctx(ssl::context::tls_client) {
    ctx.load_verify_file(ca.string());
    ctx.set_verify_mode(ssl::verify_peer);
  }
  // Connects and handshakes (checking the certificate's name "localhost").
  beast::error_code open(beast::ssl_stream<beast::tcp_stream>& s, unsigned short port) {
    beast::error_code ec;
    beast::get_lowest_layer(s).expires_after(10s);
    beast::get_lowest_layer(s).connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port), ec);
    if (ec) return ec;
    SSL_set_tlsext_host_name(s.native_handle(), "localhost");
    s.set_verify_callback(ssl::host_name_verification("localhost"));
    s.handshake(ssl::stream_base::client, ec);
    return ec;
  }
  net::io_context ioc;
  ssl::context ctx;
};

TEST_F(Hardening, TlsServesHttpsAndWssAndRefusesPlainHttp) {
  const fs::path cert = dir_ / "cert.pem", key = dir_ / "key.pem", other = dir_ / "other.pem",
                 other_key = dir_ / "other-key.pem";
  std::string out;
  for (const auto& [c, k] : {std::pair(cert, key), std::pair(other, other_key)})
    ASSERT_EQ(test::run("openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost -addext "
                        "subjectAltName=DNS:localhost,IP:127.0.0.1 -keyout '" +
                            k.string() + "' -out '" + c.string() + "' 2>&1",
                        &out),
              0)
        << out;
  ASSERT_TRUE(start({"--tls-cert", cert.string(), "--tls-key", key.string()}));

  TlsClient client(cert);
  {  // REST over https
    beast::ssl_stream<beast::tcp_stream> s(client.ioc, client.ctx);
    ASSERT_FALSE(client.open(s, port()));
    beast::http::request<beast::http::empty_body> req(beast::http::verb::get, "/api/v1/health", 11);
    req.set(beast::http::field::host, "localhost");
    beast::http::write(s, req);
    beast::flat_buffer buf;
    beast::http::response<beast::http::string_body> res;
    beast::http::read(s, buf, res);
    EXPECT_EQ(res.result_int(), 200u) << res.body();
    EXPECT_EQ(json::parse(res.body(), nullptr, false).value("status", ""), "ok") << res.body();
  }
  {  // the WebSocket over wss
    beast::websocket::stream<beast::ssl_stream<beast::tcp_stream>> ws(client.ioc, client.ctx);
    ASSERT_FALSE(client.open(ws.next_layer(), port()));
    beast::get_lowest_layer(ws).expires_never();
    ws.set_option(beast::websocket::stream_base::timeout::suggested(beast::role_type::client));
    ws.handshake("localhost", "/api/v1/ws");
    ws.write(net::buffer(json{{"type", "ping"}, {"request_id", 7}}.dump()));
    beast::flat_buffer buf;
    ws.read(buf);
    const json pong = json::parse(beast::buffers_to_string(buf.data()), nullptr, false);
    EXPECT_EQ(pong.value("type", ""), "pong") << pong.dump();
    EXPECT_EQ(pong.value("request_id", 0), 7);
    ws.close(beast::websocket::close_code::normal);
  }
  {  // a client that does not trust the certificate: no handshake
    TlsClient stranger(other);
    beast::ssl_stream<beast::tcp_stream> s(stranger.ioc, stranger.ctx);
    EXPECT_TRUE(stranger.open(s, port()));
  }
  // Plain HTTP on the TLS port: one 400 saying so, and closed.
  const HttpResult plain = http_get(port(), "/api/v1/health");
  expect_error(plain, 400, "tls_required");
  EXPECT_FALSE(plain.keep_alive);
  {  // still serving
    beast::ssl_stream<beast::tcp_stream> s(client.ioc, client.ctx);
    ASSERT_FALSE(client.open(s, port()));
    beast::http::request<beast::http::empty_body> req(beast::http::verb::get, "/api/v1/meshes/%2e%2e", 11);
    req.set(beast::http::field::host, "localhost");
    beast::http::write(s, req);
    beast::flat_buffer buf;
    beast::http::response<beast::http::string_body> res;
    beast::http::read(s, buf, res);
    EXPECT_EQ(res.result_int(), 400u) << res.body();
  }
}

TEST_F(Hardening, TlsWithAMissingOrMismatchedFileDoesNotStart) {
  std::string out;
  const int rc = test::run("'" + test::bin("cgview-server") + "' --port 0 --samples none --data-dir '" +
                               data_.string() + "' --tls-cert '" + (dir_ / "none.pem").string() + "' --tls-key '" +
                               (dir_ / "none.pem").string() + "' 2>&1",
                           &out);
  EXPECT_NE(rc, 0);
  EXPECT_NE(out.find("cannot read"), std::string::npos) << out;
  const int rc2 = test::run("'" + test::bin("cgview-server") + "' --port 0 --samples none --data-dir '" +
                                data_.string() + "' --tls-cert x.pem 2>&1",
                            &out);
  EXPECT_NE(rc2, 0);
  EXPECT_NE(out.find("--tls-key"), std::string::npos) << out;
  // A key that is not the certificate's.
  const fs::path cert = dir_ / "cert.pem", key = dir_ / "key.pem", stranger = dir_ / "stranger.pem";
  ASSERT_EQ(test::run("openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost -keyout '" + key.string() +
                          "' -out '" + cert.string() + "' && openssl genrsa -out '" + stranger.string() + "' 2048",
                      &out),
            0)
      << out;
  const int rc3 =
      test::run("'" + test::bin("cgview-server") + "' --port 0 --samples none --data-dir '" + data_.string() +
                    "' --tls-cert '" + cert.string() + "' --tls-key '" + stranger.string() + "'",
                &out);
  EXPECT_NE(rc3, 0);
  EXPECT_NE(out.find("not the PEM private key of the certificate"), std::string::npos) << out;
}

}  // namespace
}  // namespace cgview::test
