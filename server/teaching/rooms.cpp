#include "teaching/rooms.h"

#include <sqlite3.h>

#include "auth.h"
#include "core/errors.h"
#include "io/parse_json.h"
#include "sqlite_stmt.h"
#include "teaching/courses.h"
#include "io/zip_bundle.h"  // TooLarge

namespace cgview::server {

using nlohmann::json;
using Events = std::vector<std::pair<json, Access>>;

namespace {

bool valid_part(const std::string& p) {
  if (p.empty() || p.size() > 32) return false;
  for (unsigned char c : p)
    if (!std::islower(c) && c != '_') return false;
  return true;
}

// The meshes and jobs a state's value names: any member "mesh" or "job" (an
// id), "meshes" or "jobs" (a list of ids), at any depth.
void named_items(const json& v, std::vector<std::pair<std::string, std::string>>& out, int depth = 0) {
  if (depth > 8) return;
  if (v.is_object()) {
    for (const auto& [k, x] : v.items()) {
      const std::string kind = k == "mesh" || k == "meshes" ? "mesh" : k == "job" || k == "jobs" ? "job" : "";
      if (!kind.empty() && x.is_string()) out.emplace_back(kind, x);
      else if (!kind.empty() && x.is_array())
        for (const json& id : x)
          if (id.is_string()) out.emplace_back(kind, id);
      named_items(x, out, depth + 1);
    }
  } else if (v.is_array()) {
    for (const json& x : v) named_items(x, out, depth + 1);
  }
}

}  // namespace

Rooms::Rooms(Store& store, Courses& courses, Send send, Owns owns)
    : store_(store), courses_(courses), send_(std::move(send)), owns_(std::move(owns)) {
  db_ = open_database(store.data_dir() / "cgview.db");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS rooms (id TEXT PRIMARY KEY, course TEXT NOT NULL, presenter TEXT NOT NULL,"
           " started TEXT NOT NULL, ended TEXT);"
           "CREATE TABLE IF NOT EXISTS room_events (room TEXT NOT NULL, seq INTEGER NOT NULL, t_ms INTEGER NOT NULL,"
           " part TEXT NOT NULL, value TEXT NOT NULL, PRIMARY KEY (room, seq));"
           // Rooms live in memory: those a stopped server held are over.
           "UPDATE rooms SET ended = started WHERE ended IS NULL;",
           "rooms");
  flusher_ = std::thread([this] { flush_loop(); });
}

Rooms::~Rooms() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (flusher_.joinable()) flusher_.join();
  sqlite3_close(db_);
}

Rooms::Room& Rooms::live_locked(const std::string& room) {
  const auto it = rooms_.find(room);
  if (it == rooms_.end()) throw std::out_of_range("no live room '" + room + "'");
  return it->second;
}

json Rooms::presence_locked(const Room& r) const {
  json hands = json::array();
  for (const auto& [user, point] : r.hands) hands.push_back({{"user", user}, {"point", point}});
  std::set<std::string> users;
  for (const auto& [c, u] : r.followers) users.insert(u);
  return {{"type", "room_presence"}, {"room", r.id}, {"followers", users.size()}, {"hands", hands}};
}

// Who gets a room's events: its presenter and its followers, by name (not
// by the room's group: a follower who just left, or a room just ended, is
// told so even though the group no longer holds them).
static Access room_readers(const std::string& presenter, const std::map<std::string, std::string>& followers) {
  std::vector<std::string> users;
  for (const auto& [c, u] : followers) users.push_back(u);
  return Access{presenter, users};
}

void Rooms::record_locked(Room& r, const std::string& part, const json& value) {
  const auto t = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - r.started);
  // Written a second at a time (write_records_locked): a commit per camera
  // change would change the database's version thirty times a second, and
  // with it make every WebSocket check its token again at every event.
  records_.push_back({r.id, ++r.seq, std::int64_t(t.count()), part, value.dump()});
  wake_.notify_all();
}

void Rooms::write_records_locked() {
  if (records_.empty()) return;
  try {
    exec_sql(db_, "BEGIN", "rooms");
    for (const Record& e : records_) {
      Stmt s(db_, "INSERT INTO room_events (room, seq, t_ms, part, value) VALUES (?1, ?2, ?3, ?4, ?5)");
      s.bind(1, e.room).bind(2, e.seq).bind(3, e.t_ms).bind(4, e.part).bind(5, e.value);
      s.step();
    }
    exec_sql(db_, "COMMIT", "rooms");
  } catch (const std::exception& e) {
    // A full disk loses the recording's steps, never the lecture.
    sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    std::fprintf(stderr, "cgview-server: %zu room changes not recorded: %s\n", records_.size(), e.what());
  }
  records_.clear();
  last_write_ = std::chrono::steady_clock::now();
}

void Rooms::emit_locked(Room& r, const std::string& part, const json& value, Events& out) {
  if (part == "camera") r.last_camera = std::chrono::steady_clock::now();
  r.state[part] = value;
  record_locked(r, part, value);
  const auto t = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - r.started);
  out.emplace_back(json{{"type", "room_update"}, {"room", r.id}, {"part", part}, {"value", value}, {"t_ms", t.count()}},
                   room_readers(r.presenter, r.followers));
}

void Rooms::share_shown_locked(Room& r, const std::string&, const json& value, const Caller& caller) {
  std::vector<std::pair<std::string, std::string>> items;
  named_items(value, items);
  for (const auto& item : items) {
    if (r.shown.count(item) || !owns_ || !owns_(item.first, item.second, caller)) continue;
    store_.set_shared(item.first, item.second, {group(r.id)}, true);
    r.shown.insert(item);
  }
}

json Rooms::present(const json& msg, const Caller& caller, const std::string& connection) {
  std::string course;
  if (msg.contains("course")) {
    if (!msg["course"].is_string()) throw InvalidInput("\"course\" is a course's id");
    course = msg["course"];
    courses_.require_staff(course, caller);
  } else if (msg.value("code", json(false)) != json(true)) {
    throw InvalidInput("present takes {\"course\": ID} (its members follow) or {\"code\": true} (a join code)");
  }
  Room r;
  r.id = new_id();
  r.course = course;
  if (course.empty()) r.code = random_hex(4);
  r.presenter = caller.user;
  r.presenter_connection = connection;
  r.started = std::chrono::steady_clock::now();
  r.started_iso = now_iso8601();
  std::lock_guard lock(mutex_);
  Stmt s(db_, "INSERT INTO rooms (id, course, presenter, started) VALUES (?1, ?2, ?3, ?4)");
  s.bind(1, r.id).bind(2, course).bind(3, r.presenter).bind(4, r.started_iso);
  s.step();
  json out = {{"type", "room"}, {"room", r.id}, {"role", "presenter"}};
  if (!course.empty()) out["course"] = course;
  else out["code"] = r.code;
  rooms_[r.id] = std::move(r);
  return out;
}

json Rooms::follow(const json& msg, const Caller& caller, const std::string& connection) {
  Events events;
  json out;
  {
    std::lock_guard lock(mutex_);
    Room* r = nullptr;
    if (msg.value("room", json()).is_string()) {
      const auto it = rooms_.find(msg["room"]);
      // A code room is followed by its code; a course's by its members.
      if (it != rooms_.end() && !it->second.course.empty() && courses_.role(it->second.course, caller)) r = &it->second;
    } else if (msg.value("code", json()).is_string()) {
      for (auto& [id, room] : rooms_)
        if (!room.code.empty() && room.code == msg["code"].get<std::string>()) r = &room;
    } else {
      throw InvalidInput("follow takes {\"room\": ID} or {\"code\": CODE}");
    }
    if (!r) throw std::out_of_range("no live room to follow there");
    r->followers[connection] = caller.user;
    out = {{"type", "room_state"}, {"room", r->id}, {"presenter", r->presenter}, {"state", r->state}};
    events.emplace_back(presence_locked(*r), Access{r->presenter});
  }
  for (const auto& [e, readers] : events) send_(e, readers);
  return out;
}

void Rooms::set(const std::string& room, const std::string& part, const json& value, const Caller& caller) {
  if (!valid_part(part)) throw InvalidInput("a part is a name of 1 to 32 of [a-z_]");
  if (value.dump().size() > kMaxPartBytes)
    throw TooLarge("a part's value is at most " + std::to_string(kMaxPartBytes) + " bytes of JSON");
  Events events;
  {
    std::lock_guard lock(mutex_);
    Room& r = live_locked(room);
    if (r.presenter != caller.user) throw Forbidden("only the presenter of room " + room + " changes it");
    share_shown_locked(r, part, value, caller);
    // The camera at most every kCameraInterval, its latest value last (the flusher sends what waits).
    if (part == "camera" && std::chrono::steady_clock::now() - r.last_camera < kCameraInterval) {
      r.pending_camera = value;
      wake_.notify_all();
      return;
    }
    if (part == "camera") r.pending_camera.reset();
    emit_locked(r, part, value, events);
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::hand(const std::string& room, const json& point, const Caller& caller) {
  if (!point.is_null() && (!point.is_object() || point.dump().size() > 4096))
    throw InvalidInput("a hand's point is {\"mesh\": ID, \"position\": [x, y, z]}, or null to lower it");
  Events events;
  {
    std::lock_guard lock(mutex_);
    Room& r = live_locked(room);
    bool following = false;
    for (const auto& [c, u] : r.followers) following = following || u == caller.user;
    if (!following) throw std::out_of_range("no live room '" + room + "' that you follow");
    if (point.is_null()) r.hands.erase(caller.user);
    else r.hands[caller.user] = point;
    events.emplace_back(presence_locked(r), Access{r.presenter});
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::show_hand(const std::string& room, const std::string& user, const Caller& caller) {
  Events events;
  {
    std::lock_guard lock(mutex_);
    Room& r = live_locked(room);
    if (r.presenter != caller.user) throw Forbidden("only the presenter of room " + room + " shows a hand");
    const auto it = r.hands.find(user);
    if (it == r.hands.end()) throw std::out_of_range("no hand of '" + user + "' in room " + room);
    emit_locked(r, "hand", {{"user", user}, {"point", it->second}}, events);
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::end_locked(Room& r, Events& out) {
  if (r.pending_camera) emit_locked(r, "camera", *r.pending_camera, out);
  out.emplace_back(json{{"type", "room_ended"}, {"room", r.id}}, room_readers(r.presenter, r.followers));
  for (const auto& [kind, id] : r.shown) store_.set_shared(kind, id, {group(r.id)}, false);
  write_records_locked();
  try {
    Stmt s(db_, "UPDATE rooms SET ended = ?2 WHERE id = ?1");
    s.bind(1, r.id).bind(2, now_iso8601());
    s.step();
  } catch (const std::exception&) {
  }
  rooms_.erase(r.id);
}

void Rooms::end(const std::string& room, const Caller& caller) {
  Events events;
  {
    std::lock_guard lock(mutex_);
    Room& r = live_locked(room);
    if (r.presenter != caller.user && !caller.admin) throw Forbidden("only the presenter ends room " + room);
    end_locked(r, events);
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::leave(const std::string& room, const Caller& caller, const std::string& connection) {
  Events events;
  {
    std::lock_guard lock(mutex_);
    Room& r = live_locked(room);
    if (!r.followers.erase(connection)) throw std::out_of_range("this connection does not follow room " + room);
    const bool still =
        std::any_of(r.followers.begin(), r.followers.end(), [&](const auto& f) { return f.second == caller.user; });
    if (!still) r.hands.erase(caller.user);
    events.emplace_back(presence_locked(r), Access{r.presenter});
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::disconnected(const std::string& connection) {
  if (connection.empty()) return;
  Events events;
  {
    std::lock_guard lock(mutex_);
    std::vector<std::string> ended;
    for (auto& [id, r] : rooms_) {
      if (r.presenter_connection == connection) ended.push_back(id);
      else if (r.followers.erase(connection)) events.emplace_back(presence_locked(r), Access{r.presenter});
    }
    for (const auto& id : ended) end_locked(rooms_.at(id), events);
  }
  for (const auto& [e, readers] : events) send_(e, readers);
}

void Rooms::flush_loop() {
  std::unique_lock lock(mutex_);
  while (!stopping_) {
    bool waiting = false;
    Events events;
    for (auto& [id, r] : rooms_) {
      if (!r.pending_camera) continue;
      if (std::chrono::steady_clock::now() - r.last_camera >= kCameraInterval) {
        const json v = *r.pending_camera;
        r.pending_camera.reset();
        emit_locked(r, "camera", v, events);
      } else {
        waiting = true;
      }
    }
    if (!events.empty()) {
      lock.unlock();
      for (const auto& [e, readers] : events) send_(e, readers);
      lock.lock();
      continue;
    }
    if (!records_.empty() && std::chrono::steady_clock::now() - last_write_ >= kRecordInterval) write_records_locked();
    if (waiting) wake_.wait_for(lock, std::chrono::milliseconds(5));
    else if (!records_.empty()) wake_.wait_until(lock, last_write_ + kRecordInterval);
    else wake_.wait(lock);
  }
  write_records_locked();
}

json Rooms::list(const std::string& course, const Caller& caller) const {
  courses_.require_member(course, caller);
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT id, presenter, started, ended FROM rooms WHERE course = ?1 ORDER BY started");
  s.bind(1, course);
  json out = json::array();
  while (s.step()) {
    const bool live = rooms_.count(s.text(0)) != 0;
    out.push_back({{"room", s.text(0)},
                   {"presenter", s.text(1)},
                   {"started", s.text(2)},
                   {"ended", live ? json(nullptr) : json(s.text(3))},
                   {"live", live}});
  }
  return out;
}

json Rooms::recording(const std::string& room, const Caller& caller) {
  std::lock_guard lock(mutex_);
  write_records_locked();  // what waits to be written is part of it
  Stmt r(db_, "SELECT course, presenter, started, ended FROM rooms WHERE id = ?1");
  r.bind(1, room);
  if (!r.step()) throw std::out_of_range("no room '" + room + "'");
  const std::string course = r.text(0), presenter = r.text(1);
  const bool allowed =
      course.empty() ? caller.user == presenter || caller.admin : courses_.role(course, caller).has_value();
  if (!allowed) throw std::out_of_range("no room '" + room + "'");
  json events = json::array();
  Stmt e(db_, "SELECT t_ms, part, value FROM room_events WHERE room = ?1 ORDER BY seq");
  e.bind(1, room);
  while (e.step())
    events.push_back({{"t_ms", e.integer(0)}, {"part", e.text(1)}, {"value", parse_json_or_discarded(e.text(2))}});
  return {{"room", room},         {"course", course},   {"presenter", presenter},
          {"started", r.text(2)}, {"ended", r.text(3)}, {"live", rooms_.count(room) != 0},
          {"events", events}};
}

bool Rooms::presents(const std::string& room, const std::string& user) const {
  std::lock_guard lock(mutex_);
  const auto it = rooms_.find(room);
  return it != rooms_.end() && it->second.presenter == user;
}

std::vector<std::string> Rooms::groups_of(const std::string& user) const {
  std::lock_guard lock(mutex_);
  std::vector<std::string> out;
  for (const auto& [id, r] : rooms_) {
    bool in = r.presenter == user;
    for (const auto& [c, u] : r.followers) in = in || u == user;
    if (in) out.push_back(group(id));
  }
  return out;
}

}  // namespace cgview::server
