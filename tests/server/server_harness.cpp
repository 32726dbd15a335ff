#include "server_harness.h"

#include <gtest/gtest.h>

#include <utility>  // before Asio: Boost 1.74 uses std::exchange without it (GCC 12)

#include <boost/asio.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <regex>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "test_support.h"

namespace cgview::test {

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

std::map<pid_t, std::string> processes_naming(const fs::path& dir) {
  std::map<pid_t, std::string> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator("/proc", ec)) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = read_bytes(e.path() / "cmdline");
    for (char& c : cmdline)
      if (c == '\0') c = ' ';
    if (cmdline.find(dir.string()) != std::string::npos && cmdline.find("cgview-server") == std::string::npos)
      found[pid_t(std::stoi(name))] = cmdline;
  }
  return found;
}

std::map<pid_t, std::string> processes_outliving(const fs::path& dir, std::chrono::milliseconds limit,
                                                 std::string_view but) {
  const auto end = std::chrono::steady_clock::now() + limit;
  auto naming = [&] {
    std::map<pid_t, std::string> found = processes_naming(dir);
    if (!but.empty()) std::erase_if(found, [&](const auto& p) { return p.second.find(but) != std::string::npos; });
    return found;
  };
  std::map<pid_t, std::string> left = naming();
  while (!left.empty() && std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    left = naming();
  }
  for (const auto& [pid, cmdline] : left) ::kill(pid, SIGKILL);
  return left;
}

// ---------------------------------------------------------------- the server

bool ServerProcess::start(const fs::path& data_dir, const std::vector<std::string>& extra, const fs::path& log_dir) {
  kill_now();
  out_ = log_dir / ("stdout-" + std::to_string(++starts_) + ".txt");
  err_ = log_dir / ("stderr-" + std::to_string(starts_) + ".txt");
  std::vector<std::string> args = {test::bin("cgview-server"), "--host",    "127.0.0.1", "--port", "0", "--data-dir",
                                   data_dir.string(),          "--samples", "none"};
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
  const std::regex line_re(R"(CGView serving https?://([^/:]+):([0-9]+)/)");
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
                << read_bytes(out_) << "\nstderr:\n"
                << read_bytes(err_);
  kill_now();
  return false;
}

int ServerProcess::stop(int sig, std::chrono::milliseconds limit) {
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

void ServerProcess::kill_now() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }
}

bool ServerProcess::alive() {
  if (pid_ <= 0) return false;
  int status = 0;
  if (::waitpid(pid_, &status, WNOHANG) == pid_) {
    pid_ = -1;
    return false;
  }
  return true;
}

long ServerProcess::rss_kb() const {
  std::ifstream f("/proc/" + std::to_string(pid_) + "/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  return -1;
}

std::string ServerProcess::stderr_text() const { return read_bytes(err_); }

// ---------------------------------------------------------------- HTTP

namespace {

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

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

http::verb to_verb(Method m) {
  switch (m) {
    case Method::get:
      return http::verb::get;
    case Method::head:
      return http::verb::head;
    case Method::post:
      return http::verb::post;
    case Method::put:
      return http::verb::put;
    case Method::delete_:
      return http::verb::delete_;
  }
  return http::verb::unknown;
}

// The plain result of a read that ended with `ec` (or timed out).
HttpResult result_of(bool done, const beast::error_code& ec, http::response_parser<http::string_body>& parser) {
  HttpResult out;
  out.timed_out = !done;
  out.ec = done ? ec : beast::error_code(net::error::timed_out);
  if (out.ec) return out;
  http::response<http::string_body> res = parser.release();
  out.status = res.result_int();
  out.keep_alive = res.keep_alive();
  for (const auto& field : res) out.headers[lower(std::string(field.name_string()))] = std::string(field.value());
  out.body = std::move(res.body());
  return out;
}

}  // namespace

std::string HttpResult::header(const std::string& name) const {
  const auto it = headers.find(lower(name));
  return it == headers.end() ? std::string() : it->second;
}

HttpResult http_call(unsigned short port, Method method, const std::string& target, std::string body,
                     std::chrono::milliseconds limit) {
  HttpResult out;
  net::io_context ioc;
  tcp::socket socket(ioc);
  std::optional<beast::error_code> connected, wrote, read;
  socket.async_connect(local(port), [&](beast::error_code ec) { connected = ec; });
  if (!run_until(
          ioc, [&] { return connected.has_value(); }, limit) ||
      *connected) {
    out.timed_out = !connected.has_value();
    out.ec = connected.value_or(net::error::timed_out);
    return out;
  }
  http::request<http::string_body> req{to_verb(method), target, 11};
  req.set(http::field::host, "127.0.0.1");
  req.set(http::field::user_agent, "cgview-test");
  req.keep_alive(false);
  req.body() = std::move(body);
  req.prepare_payload();
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  parser.body_limit(std::numeric_limits<std::uint64_t>::max());
  parser.skip(method == Method::head);  // a HEAD response has no body, whatever its Content-Length
  http::async_write(socket, req, [&](beast::error_code ec, std::size_t) { wrote = ec; });
  http::async_read(socket, buffer, parser, [&](beast::error_code ec, std::size_t) { read = ec; });
  const bool done = run_until(
      ioc, [&] { return read.has_value(); }, limit);
  beast::error_code ignored;
  socket.close(ignored);
  run_until(
      ioc, [&] { return wrote.has_value() && read.has_value(); }, 5s);
  return result_of(done, done ? *read : beast::error_code(), parser);
}

HttpResult http_get(unsigned short port, const std::string& target) { return http_call(port, Method::get, target); }

HttpResult http_raw(unsigned short port, const std::string& bytes, std::chrono::milliseconds limit) {
  net::io_context ioc;
  tcp::socket s(ioc);
  beast::error_code ec;
  s.connect(local(port), ec);
  if (!ec) net::write(s, net::buffer(bytes), ec);
  if (ec) {
    HttpResult out;
    out.ec = ec;
    return out;
  }
  beast::flat_buffer buffer;
  http::response_parser<http::string_body> parser;
  std::optional<beast::error_code> read;
  http::async_read(s, buffer, parser, [&](beast::error_code e, std::size_t) { read = e; });
  const bool done = run_until(
      ioc, [&] { return read.has_value(); }, limit);
  if (!done) {
    s.close(ec);
    run_until(
        ioc, [&] { return read.has_value(); }, 5s);
  }
  return result_of(done, done ? *read : beast::error_code(), parser);
}

struct HttpConnection::Impl {
  net::io_context ioc;
  tcp::socket socket{ioc};
  beast::flat_buffer buffer;
};

HttpConnection::HttpConnection() : impl_(std::make_unique<Impl>()) {}
HttpConnection::~HttpConnection() = default;

std::error_code HttpConnection::connect(unsigned short port) {
  beast::error_code ec;
  impl_->socket.connect(local(port), ec);
  return ec;
}

HttpResult HttpConnection::get(const std::string& target, std::chrono::milliseconds limit) {
  Impl& c = *impl_;
  http::request<http::empty_body> req{http::verb::get, target, 11};
  req.set(http::field::host, "127.0.0.1");
  req.keep_alive(true);
  std::optional<beast::error_code> done;
  http::response_parser<http::string_body> parser;
  http::async_write(c.socket, req, [&](beast::error_code ec, std::size_t) {
    if (ec) done = ec;
    else http::async_read(c.socket, c.buffer, parser, [&](beast::error_code ec2, std::size_t) { done = ec2; });
  });
  const bool in_time = run_until(
      c.ioc, [&] { return done.has_value(); }, limit);
  if (!in_time) {
    beast::error_code ignored;
    c.socket.close(ignored);
    run_until(
        c.ioc, [&] { return done.has_value(); }, 5s);
  }
  return result_of(in_time, in_time ? *done : beast::error_code(), parser);
}

// ---------------------------------------------------------------- WebSocket

struct WsClient::Impl {
  net::io_context ioc;
  websocket::stream<tcp::socket> ws{ioc};

  template <class Start>
  beast::error_code op(Start start, std::chrono::milliseconds limit = 30s) {
    auto result = std::make_shared<std::optional<beast::error_code>>();
    start([result](beast::error_code ec, auto&&...) { *result = ec; });
    if (run_until(
            ioc, [&] { return result->has_value(); }, limit))
      return **result;
    beast::error_code ignored;
    ws.next_layer().close(ignored);  // the pending operation ends with an error
    run_until(
        ioc, [&] { return result->has_value(); }, 5s);
    return net::error::timed_out;
  }
};

WsClient::WsClient() : impl_(std::make_unique<Impl>()) {}
WsClient::~WsClient() = default;

std::error_code WsClient::connect(unsigned short port, const std::string& target) {
  Impl& c = *impl_;
  beast::error_code ec = c.op([&](auto h) { c.ws.next_layer().async_connect(local(port), h); });
  if (ec) return ec;
  c.ws.next_layer().set_option(tcp::no_delay(true), ec);
  return c.op([&](auto h) { c.ws.async_handshake("127.0.0.1:" + std::to_string(port), target, h); });
}

std::error_code WsClient::send(const json& j) { return send_text(j.dump()); }

std::error_code WsClient::send_text(const std::string& text) {
  Impl& c = *impl_;
  c.ws.text(true);
  return c.op([&](auto h) { c.ws.async_write(net::buffer(text), h); });
}

std::error_code WsClient::send_binary(const std::string& bytes) {
  Impl& c = *impl_;
  c.ws.binary(true);
  return c.op([&](auto h) { c.ws.async_write(net::buffer(bytes), h); });
}

std::optional<WsClient::Message> WsClient::read(std::chrono::milliseconds limit) {
  Impl& c = *impl_;
  beast::flat_buffer buffer;
  last_ = c.op([&](auto h) { c.ws.async_read(buffer, h); }, limit);
  if (last_) return std::nullopt;
  return Message{c.ws.got_binary(), beast::buffers_to_string(buffer.data())};
}

json WsClient::reply(std::chrono::milliseconds limit) {
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

bool WsClient::ping(std::uint64_t request_id) {
  if (send({{"type", "ping"}, {"request_id", request_id}})) return false;
  const json j = reply();
  return j == json{{"type", "pong"}, {"request_id", request_id}};
}

std::error_code WsClient::close() {
  Impl& c = *impl_;
  return c.op([&](auto h) { c.ws.async_close(websocket::close_code::normal, h); }, 10s);
}

void WsClient::abort() {
  beast::error_code ec;
  impl_->ws.next_layer().set_option(net::socket_base::linger(true, 0), ec);
  impl_->ws.next_layer().close(ec);
}

// ---------------------------------------------------------------- fixture

void ServerFixture::SetUp() {
  const std::string name = tag_ + ::testing::UnitTest::GetInstance()->current_test_info()->name();
  if (outside_tmp_) {
    dir_ = fs::path("/var/tmp") / ("cgview-test-" + std::to_string(::getpid())) / name;
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  } else {
    dir_ = temp_dir(name);
  }
  data_ = dir_ / "data";
}

void ServerFixture::TearDown() {
  if (HasFailure() && server_.pid() > 0) std::cerr << "server stderr:\n" << server_.stderr_text();
  server_.kill_now();
  std::error_code ec;
  if (!HasFailure()) fs::remove_all(dir_, ec);           // kept for a look after a failure
  if (outside_tmp_) fs::remove(dir_.parent_path(), ec);  // when it is empty
}

void ServerFixture::expect_healthy() {
  const HttpResult h = http_get(port(), "/api/v1/health");
  ASSERT_FALSE(h.ec) << "health: " << h.ec.message();
  EXPECT_EQ(h.status, 200u);
  EXPECT_EQ(h.body_json().value("status", ""), "ok");
}

void ServerFixture::expect_error(const HttpResult& r, unsigned status, const std::string& code) {
  ASSERT_FALSE(r.ec) << r.ec.message();
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.header("Content-Type"), "application/json");
  const json j = r.body_json();
  EXPECT_EQ(j.value("error", ""), code) << r.body;
  EXPECT_TRUE(j.contains("detail") && j["detail"].is_string()) << r.body;
}

HttpResult call_as(unsigned short port, const std::string& token, const std::string& method, const std::string& target,
                   const std::string& body) {
  return http_raw(port, method + " " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer " + token +
                            "\r\nContent-Length: " + std::to_string(body.size()) + "\r\nConnection: close\r\n\r\n" +
                            body);
}

nlohmann::json wait_job_end(unsigned short port, const std::string& id, std::chrono::milliseconds limit,
                            const std::string& token) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  const std::string target = "/api/v1/jobs/" + id;
  nlohmann::json j;
  for (;;) {
    j = (token.empty() ? http_get(port, target) : call_as(port, token, "GET", target)).body_json();
    const std::string state = j.is_object() ? j.value("state", "") : "";
    if (state != "queued" && state != "running") return j;
    if (std::chrono::steady_clock::now() >= deadline) break;
    // A job's end has no reply to wait on here; 20 ms keeps the poll cheap
    // for the server and the wait short for the test.
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ADD_FAILURE() << "job " << id << " did not end within " << limit.count() << " ms: " << j.dump();
  return j;
}

std::string server_command(const fs::path& data, const std::string& args) {
  std::ostringstream cmd;  // (one + chain of strings here trips GCC 12's -Wrestrict)
  cmd << "'" << bin("cgview-server") << "' --data-dir '" << data.string() << "' " << args << " 2>/dev/null";
  std::string out;
  if (FILE* p = ::popen(cmd.str().c_str(), "r")) {
    char buf[512];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
    ::pclose(p);
  }
  while (!out.empty() && out.back() == '\n') out.pop_back();
  return out;
}

}  // namespace cgview::test
