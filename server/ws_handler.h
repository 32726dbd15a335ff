// The WebSocket's messages (protocol/API.md): a message and a connection's
// state in, replies out, and no sockets, as the HTTP router is.  The session
// calls receive() on its strand and runs the work it returns on a worker
// thread; tests and the fuzz target call handle(), which does both at once.
#pragma once

#include <chrono>
#include <cstddef>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "auth.h"
#include "core/voxel_grid.h"
#include "frames.h"
#include "artifacts/artifact_codec.h"

namespace cgview::server {

class MeshService;
class RateLimiter;
class Rooms;

// A message to a client: JSON text, or a binary frame (its header, then a
// view into a payload that `keep` holds: the cached Draco bytes are never copied).
struct WsOut {
  std::string head;
  std::shared_ptr<const void> keep;
  std::string_view body;
  bool binary = false;
  std::size_t size() const { return head.size() + body.size(); }
  // A JSON message (a detail quoting a file's invalid UTF-8 is replaced, not a reason to fail).
  static WsOut text(const nlohmann::json& message);
};
using WsEmit = std::function<void(WsOut)>;

// What the handler knows of one connection; read and changed on its strand only.
struct WsConnection {
  std::string address;  // the client's, for the rate limit
  bool loopback = false;
  // "Bearer TOKEN", checked again for each message and event, so that a
  // revoked token stops an open session at once; empty: the local user.
  std::string authorization;
  std::optional<Caller> caller;  // set once authenticated
  bool close = false;            // refused: the session closes once the replies are sent
  std::string id;                // this connection's, once it presents or follows a live room
  // The caller as last checked for an event, and the store's version then
  // (Store::version): an event checks the token again only when that changed
  // or a second passed, not thousands of times a second to a lecture's followers.
  std::optional<Caller> checked;
  std::int64_t checked_version = -1;
  std::chrono::steady_clock::time_point checked_at{};
};

struct WsHandlerConfig {
  std::size_t chunk_bytes = protocol::kDefaultChunkBytes;  // of binary frames
  std::size_t max_message_bytes = std::size_t(1) << 20;    // what too_big() says
  std::size_t kept_grids = 4;                              // decoded voxel grids kept for slicing
};

// A server's job artifacts as the handler reads them (JobScheduler's).
struct JobArtifacts {
  // An artifact in a format, if the caller may read it (JobScheduler::artifact):
  // std::out_of_range for an unknown job or artifact, UnsupportedFormat for the wrong kind.
  std::function<ExportedArtifact(const std::string& job, const std::string& name, const std::string& format,
                                 const Caller&)>
      read;
  // Throws std::out_of_range unless the caller may read the job
  // (JobScheduler::access): checked before a grid kept from before serves them.
  std::function<void(const std::string& job, const Caller&)> check_readable;
};

class WsHandler {
 public:
  // artifacts: empty on a server that runs no jobs.
  WsHandler(MeshService& meshes, JobArtifacts artifacts, const Auth& auth, RateLimiter* rate,
            WsHandlerConfig config = {});

  using Work = std::function<void(const WsEmit&)>;
  // On the connection's strand: parses the message, checks its token and
  // rate, answers auth and ping through `emit`; returns the work left for a
  // worker thread (reading, encoding, streaming), or an empty function.
  Work receive(std::string_view text, bool binary, WsConnection& conn, const WsEmit& emit) const;
  // receive() and its work at once, the replies in order.
  std::vector<WsOut> handle(std::string_view text, WsConnection& conn, bool binary = false) const;
  // The reply to a message over max_message_bytes (the session then closes).
  WsOut too_big() const;
  // Live rooms (teaching/rooms.h): their messages are present, follow,
  // room_set, raise_hand, show_hand and room_end.  Set before serving.
  void set_rooms(Rooms* rooms) { rooms_ = rooms; }
  // The connection closed: its rooms hear of it.
  void closed(const WsConnection& conn) const;
  // Whether an event for `readers` goes to this connection; a revoked token
  // gets its refusal through `emit` instead (and conn.close).
  bool admits_event(WsConnection& conn, const Access& readers, const WsEmit& emit) const;

 private:
  std::optional<Caller> still_authorized(WsConnection& conn, const WsEmit& emit) const;
  // A room's message, answered on the strand (light work); false: not one.
  bool room_message(const std::string& type, const nlohmann::json& msg, const nlohmann::json& id, WsConnection& conn,
                    const Caller& caller, const WsEmit& emit) const;
  void get_mesh(const nlohmann::json& msg, const nlohmann::json& id, const Caller& caller, const WsEmit& emit) const;
  void get_slice(const nlohmann::json& msg, const nlohmann::json& id, const Caller& caller, const WsEmit& emit) const;
  void get_animation(const nlohmann::json& msg, const nlohmann::json& id, const Caller& caller,
                     const WsEmit& emit) const;
  // The begin message, the payload in binary frames of `kind`, the end message.
  void stream(nlohmann::json begin, protocol::FrameKind kind, const nlohmann::json& id,
              std::shared_ptr<const void> keep, std::string_view payload, const std::string& end_type,
              const WsEmit& emit) const;

  MeshService& meshes_;
  // The voxel grid artifact `name` of a job, decoded: the last few are kept,
  // so that paging through slices does not read and decode the file each time
  // (a done job's artifacts never change).
  std::shared_ptr<const VoxelGrid> grid(const std::string& job, const std::string& name, const Caller& caller) const;

  JobArtifacts artifacts_;
  mutable std::mutex grids_mutex_;
  mutable std::list<std::pair<std::string, std::shared_ptr<const VoxelGrid>>> grids_;  // newest first
  const Auth& auth_;
  RateLimiter* rate_;
  WsHandlerConfig config_;
  Rooms* rooms_ = nullptr;
};

}  // namespace cgview::server
