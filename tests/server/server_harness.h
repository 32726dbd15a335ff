// The real cgview-server as a child process, and timed HTTP and WebSocket
// clients for it, and the fixture that starts it, shared by the server's
// integration suites (server_integration_test, jobs_test, hardening_test,
// render_endpoint_test).  Boost.Beast stays in the .cpp:
// results are plain strings, ints and std::error_code.
#pragma once

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include <sys/types.h>

namespace cgview::test {

// The whole file, binary.
std::string read_bytes(const std::filesystem::path& p);

// The processes whose command line names `dir`, the server's own left out:
// a job's bubblewrap does (its job directory is bound in).
std::map<pid_t, std::string> processes_naming(const std::filesystem::path& dir);

// Waits up to `limit` for processes_naming(dir) to be empty; those still
// there are killed (this test's own, by id) and returned, to be reported.
// Those whose command line holds `but` (when not empty) are left out.
std::map<pid_t, std::string> processes_outliving(const std::filesystem::path& dir, std::chrono::milliseconds limit,
                                                 std::string_view but = {});

// In the command line of a running server's pre-started worker (its
// bubblewrap binds runs/warm-N): it waits for the next job, no job's.
inline constexpr std::string_view kPrestartedWorker = "/runs/warm-";

// ---------------------------------------------------------------- the server

// One cgview-server child process; killed when this goes out of scope.
class ServerProcess {
 public:
  ServerProcess() = default;
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;
  ~ServerProcess() { kill_now(); }

  // Starts the binary (--host 127.0.0.1 --port 0 --data-dir DATA_DIR
  // --samples none, then EXTRA; stdout and stderr to files in LOG_DIR) and
  // waits for its "CGView serving http://HOST:PORT/" line; false (with a
  // failure added) if it does not come.
  bool start(const std::filesystem::path& data_dir, const std::vector<std::string>& extra,
             const std::filesystem::path& log_dir);

  // Sends a signal and waits for the exit; the exit status (128 + signal when
  // killed by one), or -1 (killed after the time limit).
  int stop(int sig, std::chrono::milliseconds limit = std::chrono::seconds(10));

  void kill_now();
  bool alive();

  // Resident memory in kB (VmRSS), or -1.
  long rss_kb() const;

  unsigned short port() const { return port_; }
  pid_t pid() const { return pid_; }
  std::string stderr_text() const;

 private:
  pid_t pid_ = -1;
  unsigned short port_ = 0;
  int starts_ = 0;
  std::filesystem::path out_, err_;
};

// ---------------------------------------------------------------- HTTP

enum class Method { get, head, post, put, delete_ };

struct HttpResult {
  std::error_code ec;      // of the read; set when no response came
  bool timed_out = false;  // no response within the limit (ec is set too)
  unsigned status = 0;
  std::string body;
  std::map<std::string, std::string> headers;  // names in lower case
  bool keep_alive = false;

  // A header's value by its name (any case); empty when absent.
  std::string header(const std::string& name) const;
  nlohmann::json body_json() const { return nlohmann::json::parse(body, nullptr, false); }
};

// One request on its own connection (Connection: close).  The body is
// written while the response is read, as a client must to see an early
// answer (413) to a large upload.
HttpResult http_call(unsigned short port, Method method, const std::string& target, std::string body = "",
                     std::chrono::milliseconds limit = std::chrono::seconds(30));
HttpResult http_get(unsigned short port, const std::string& target);

// Raw bytes (not necessarily HTTP) written on a new connection, then one
// HTTP response read.
HttpResult http_raw(unsigned short port, const std::string& bytes,
                    std::chrono::milliseconds limit = std::chrono::seconds(10));
// One request with "Authorization: Bearer TOKEN" (http_raw, Connection: close).
HttpResult call_as(unsigned short port, const std::string& token, const std::string& method, const std::string& target,
                   const std::string& body = "");

// Polls GET /api/v1/jobs/ID (as `token` when not empty) until the job
// leaves queued and running; the last Job seen.  A job still queued or
// running after `limit` is a failure added to the test, with its Job.
nlohmann::json wait_job_end(unsigned short port, const std::string& id,
                            std::chrono::milliseconds limit = std::chrono::seconds(60), const std::string& token = "");

// cgview-server ARGS... on a data directory (user add, user revoke, ...); its
// stdout without the final newlines.
std::string server_command(const std::filesystem::path& data, const std::string& args);

// One keep-alive connection for several GET requests.
class HttpConnection {
 public:
  HttpConnection();
  ~HttpConnection();
  HttpConnection(const HttpConnection&) = delete;
  HttpConnection& operator=(const HttpConnection&) = delete;

  std::error_code connect(unsigned short port);
  // GET with Connection: keep-alive.
  HttpResult get(const std::string& target, std::chrono::milliseconds limit = std::chrono::seconds(10));

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------- WebSocket

// A WebSocket client on its own io_context, every operation bounded in time.
class WsClient {
 public:
  WsClient();
  ~WsClient();
  WsClient(const WsClient&) = delete;
  WsClient& operator=(const WsClient&) = delete;

  std::error_code connect(unsigned short port, const std::string& target = "/api/v1/ws");

  std::error_code send(const nlohmann::json& j);
  std::error_code send_text(const std::string& text);
  std::error_code send_binary(const std::string& bytes);

  struct Message {
    bool binary = false;
    std::string data;
  };
  // The next message; nullopt on an error (last_error() says which).
  std::optional<Message> read(std::chrono::milliseconds limit = std::chrono::seconds(30));
  // The next text message that is not an event (mesh_added, mesh_deleted),
  // parsed; events are kept in events().
  nlohmann::json reply(std::chrono::milliseconds limit = std::chrono::seconds(30));

  bool ping(std::uint64_t request_id);

  std::error_code close();
  // Drops the TCP connection with a reset, no close handshake.
  void abort();

  std::error_code last_error() const { return last_; }
  std::vector<nlohmann::json>& events() { return events_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::error_code last_;
  std::vector<nlohmann::json> events_;
};

// ---------------------------------------------------------------- fixture

// The fixture of the suites that start the real server: dir_ (a fresh temp
// directory named TAG + the test's name), data_ (dir_/data, not created) and
// server_.  After a failure the server's stderr is printed and dir_ kept.
// A shell expression, in a wrapper script given as --worker, for the
// directory its worker writes in: job.json's "out" ($1 is job.json).
inline constexpr const char* kWorkerOutSh = "$(sed 's/.*\"out\":\"\\([^\"]*\\)\".*/\\1/' \"$1\")";

class ServerFixture : public ::testing::Test {
 protected:
  // `outside_tmp`: dir_ under /var/tmp, not /tmp.  Every job sees a /tmp
  // of its own, so a sandbox test whose data lay under /tmp would pass
  // whether or not the sandbox hid the data directory.
  explicit ServerFixture(std::string tag, bool outside_tmp = false) : tag_(std::move(tag)), outside_tmp_(outside_tmp) {}
  void SetUp() override;
  void TearDown() override;
  unsigned short port() const { return server_.port(); }

  // GET /api/v1/health answers 200 {"status": "ok"}.
  void expect_healthy();
  // R is an error: STATUS with a JSON {"error": CODE, "detail": "..."} body.
  static void expect_error(const HttpResult& r, unsigned status, const std::string& code);

  std::filesystem::path dir_, data_;
  ServerProcess server_;

 private:
  std::string tag_;
  bool outside_tmp_ = false;
};

}  // namespace cgview::test
