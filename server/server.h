// cgview-server: HTTP and WebSocket on one port (Boost.Beast), split as
// Beast's chat-multi example: a listener, one session per HTTP connection,
// one per WebSocket, and shared state.  Geometry never runs on the I/O
// thread: requests go to a worker pool and their results are posted back to
// the session's strand through its write queue.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "jobs/scheduler.h"
#include "sandbox.h"
#include "render/egl_context.h"

namespace cgview::server {

struct ServerConfig {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  // 0: any free port
  std::filesystem::path data_dir = "cgview-data";
  std::filesystem::path static_dir;                          // the built web client
  std::size_t chunk_bytes = std::size_t(4) << 20;            // WebSocket binary chunk size
  std::size_t max_write_queue_bytes = std::size_t(1) << 30;  // per WebSocket, then the client is dropped

  // Limits (docs/DEPLOYMENT.md, "Limits and hardening").  A request over a
  // size limit is answered 431 (headers) or 413 (body), one too slow 408,
  // and its connection is closed; the server serves the others meanwhile.
  std::size_t max_header_bytes = std::size_t(64) << 10;     // request line and headers
  std::size_t max_upload_bytes = std::size_t(256) << 20;    // a request's body
  std::size_t max_ws_message_bytes = std::size_t(1) << 20;  // client messages are small JSON
  // A request's line and headers must arrive within request_timeout_s of its
  // first byte; its body then at min_body_rate bytes per second on average
  // (so the deadline of an upload grows with its size): one byte a second is
  // cut off, a 256 MB upload over a slow line is not.
  double request_timeout_s = 30;
  double min_body_rate = 64 << 10;
  // A keep-alive connection with no request begun for this long is closed.
  double idle_timeout_s = 60;
  // A WebSocket that sends nothing is pinged after half this time and
  // closed when the pong does not come by the end of it.
  double ws_idle_timeout_s = 60;
  double write_timeout_s = 120;  // a response that the client does not read
  // Open connections of one address (0: no cap); over: 503.  -1, the
  // default: kDefaultConnectionsPerIp for each address but loopback's.
  int max_connections_per_ip = -1;
  static constexpr int kDefaultConnectionsPerIp = 1024;
  // A WebSocket that has not authenticated within this many seconds (a
  // token in its upgrade, or an "auth" message) is closed, where a token is
  // needed (off loopback, or --auth required).
  double ws_auth_timeout_s = 5;
  // Requests (REST under /api/ and WebSocket messages) per token, or per
  // address for requests without one (not counted from loopback without a
  // token: the local user): a token bucket of rate_burst, refilled at
  // rate_per_s; over: 429 with Retry-After.  0: no limit.
  double rate_per_s = 50;
  double rate_burst = 200;

  // TLS built in (Beast over OpenSSL): both PEM files, or neither (plain
  // HTTP; TLS then comes from a proxy, docker/Caddyfile).
  std::filesystem::path tls_cert, tls_key;
  int workers = 2;
  // Every request carries a bearer token.  A server on a non-loopback
  // address needs tokens whatever this says.
  bool auth_required = false;
  render::GlPlatform gl_platform = render::GlPlatform::automatic;  // EGL platform of render.png
  JobConfig jobs;                                                  // the worker executable, pool size, limits
  // Uploads are read in a child process (this program, cgview-read), with
  // the jobs' memory limit and this time limit: a file over either is a 413,
  // one that crashes its reader a 400, and the server goes on.  Empty: read
  // in the server's own process.
  std::filesystem::path reader;
  double upload_timeout_s = 120;
  PreviewConfig preview;  // when get_mesh with lod "progressive" first streams a decimated preview
  // Where each job's worker starts (sandbox.h), and users' plugins
  // (plugin_service.h): off for users other than the local one where the
  // sandbox cannot start, unless plugins_without_sandbox says otherwise.
  SandboxConfig sandbox;
  bool plugins_without_sandbox = false;
  std::filesystem::path plugin_dir;  // the lab's plugins, for every user (--plugin-dir)
};

class Server {
 public:
  explicit Server(const ServerConfig& config);  // binds; throws on failure
  ~Server();
  unsigned short port() const;  // the bound port
  bool tls() const;             // serving https:// and wss://
  class MeshService& meshes();
  JobScheduler& jobs();
  void run();   // serves until stop(); returns then
  void stop();  // thread-safe

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cgview::server
