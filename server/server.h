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

#include "jobs.h"
#include "render/egl_context.h"

namespace cgview::server {

struct ServerConfig {
  std::string host = "127.0.0.1";
  unsigned short port = 8080;  // 0: any free port
  std::filesystem::path data_dir = "cgview-data";
  std::filesystem::path static_dir;  // the built web client
  std::size_t max_upload_bytes = std::size_t(256) << 20;
  std::size_t chunk_bytes = std::size_t(4) << 20;         // WebSocket binary chunk size
  std::size_t max_ws_message_bytes = std::size_t(1) << 20;  // client messages are small JSON
  std::size_t max_write_queue_bytes = std::size_t(1) << 30; // per WebSocket, then the client is dropped
  int workers = 2;
  // Every request carries a bearer token.  A server on a non-loopback
  // address needs tokens whatever this says.
  bool auth_required = false;
  render::GlPlatform gl_platform = render::GlPlatform::automatic;  // EGL platform of render.png
  JobConfig jobs;  // the worker executable, pool size, limits
  PreviewConfig preview;  // when get_mesh with lod "progressive" first streams a decimated preview
};

class Server {
 public:
  explicit Server(const ServerConfig& config);  // binds; throws on failure
  ~Server();
  unsigned short port() const;  // the bound port
  class MeshService& meshes();
  JobScheduler& jobs();
  void run();   // serves until stop(); returns then
  void stop();  // thread-safe

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cgview::server
