// Live lectures: a room on the server where one presenter's viewer state
// reaches every follower's, and is recorded.
//
// The presenter (a course's teacher or assistant, for its members; or
// anyone, with a join code of the room's own) is the room's only writer.
// The state is the view-link state the viewer already restores, in parts
// (camera, meshes, display, field, selection, slice, skeletons, code, ...),
// the newest value of each part winning; the camera is sent on at most 30
// times a second, its latest value last.  Followers get the whole state when
// they join, then each change, as events to the group "room:ID" (which the
// WebSocket's event filter already reads, as it reads a course's): no
// render and no job per follower, and what the presenter shows (their
// meshes, their jobs) is readable by the followers while the room lasts.
// Followers raise hands with a point picked on a mesh; the presenter sees
// them with names and the number following, never a follower's screen.
// Every change is recorded with its time; a course's members replay it.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "store.h"

struct sqlite3;

namespace cgview::server {

class Courses;

class Rooms {
 public:
  static constexpr std::chrono::milliseconds kCameraInterval{33};  // 30 a second
  static constexpr std::size_t kMaxPartBytes = 256 * 1024;         // one part's value, as JSON
  static constexpr std::chrono::seconds kRecordInterval{1};        // how often the recording is written
  // Sends an event to the readers' WebSockets (the server's broadcast).
  using Send = std::function<void(const nlohmann::json& event, const Access& readers)>;

  // Whether the caller owns a mesh or job (kind "mesh" or "job"): what a
  // presenter shows of their own, the room's followers read while it lasts.
  using Owns = std::function<bool(const std::string& kind, const std::string& id, const Caller& caller)>;

  Rooms(Store& store, Courses& courses, Send send, Owns owns);
  ~Rooms();
  Rooms(const Rooms&) = delete;
  Rooms& operator=(const Rooms&) = delete;

  // `connection`: the caller's WebSocket (a follower is counted by it).
  // present: {"course"} (its staff) or {"code": true} (a room with a join
  // code of its own) → {"room", "code"?, "course"?}.  Throws InvalidInput,
  // Forbidden, std::out_of_range.
  nlohmann::json present(const nlohmann::json& msg, const Caller& caller, const std::string& connection);
  // follow: {"room"} (a member of its course) or {"code"} → {"room", "state",
  // "presenter", "hands"?}: the whole state at once.
  nlohmann::json follow(const nlohmann::json& msg, const Caller& caller, const std::string& connection);
  // The presenter's change of one part; anyone else is Forbidden.
  void set(const std::string& room, const std::string& part, const nlohmann::json& value, const Caller& caller);
  // A follower's hand, with a point on a mesh (or lowered: point null); the presenter sees it.
  void hand(const std::string& room, const nlohmann::json& point, const Caller& caller);
  // The presenter shows a follower's hand to everybody (part "hand").
  void show_hand(const std::string& room, const std::string& user, const Caller& caller);
  // The presenter ends the room (also when their last WebSocket closes).
  void end(const std::string& room, const Caller& caller);
  // Whether `user` presents the live room (their stream skips the rate limit).
  bool presents(const std::string& room, const std::string& user) const;
  // A follower stops following (its WebSocket stays open): it is no longer
  // counted, gets no more updates, and its hand is lowered.
  void leave(const std::string& room, const Caller& caller, const std::string& connection);
  // A WebSocket closed: its follows end, and a presenter's room with it.
  void disconnected(const std::string& connection);

  // GET /api/v1/courses/{id}/rooms: live and recorded rooms of a course (its members).
  nlohmann::json list(const std::string& course, const Caller& caller) const;
  // GET /api/v1/rooms/{id}/recording: {"room", "started", "ended", "events":
  // [{"t_ms", "part", "value"}]} for the course's members (a code room's: its presenter).
  nlohmann::json recording(const std::string& room, const Caller& caller);
  // "room:ID" for each room the user presents or follows (Caller::groups).
  std::vector<std::string> groups_of(const std::string& user) const;
  static std::string group(const std::string& room) { return "room:" + room; }

 private:
  struct Room {
    std::string id, course, code, presenter, presenter_connection;
    std::chrono::steady_clock::time_point started;
    std::string started_iso;
    nlohmann::json state = nlohmann::json::object();
    std::map<std::string, std::string> followers;         // connection -> user
    std::map<std::string, nlohmann::json> hands;          // user -> point
    std::set<std::pair<std::string, std::string>> shown;  // (kind, id) shared with the room
    std::optional<nlohmann::json> pending_camera;
    std::chrono::steady_clock::time_point last_camera{};
    std::int64_t seq = 0;
  };
  Room& live_locked(const std::string& room);
  void record_locked(Room& r, const std::string& part, const nlohmann::json& value);
  void write_records_locked();
  void emit_locked(Room& r, const std::string& part, const nlohmann::json& value,
                   std::vector<std::pair<nlohmann::json, Access>>& out);
  void share_shown_locked(Room& r, const std::string& part, const nlohmann::json& value, const Caller& caller);
  void end_locked(Room& r, std::vector<std::pair<nlohmann::json, Access>>& out);
  nlohmann::json presence_locked(const Room& r) const;
  void flush_loop();

  Store& store_;
  Courses& courses_;
  Send send_;
  Owns owns_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::map<std::string, Room> rooms_;  // live ones
  struct Record {
    std::string room;
    std::int64_t seq, t_ms;
    std::string part, value;
  };
  std::vector<Record> records_;  // changes not yet written
  std::chrono::steady_clock::time_point last_write_{};
  std::condition_variable wake_;
  bool stopping_ = false;
  std::thread flusher_;
};

}  // namespace cgview::server
