#include "teaching/courses.h"

#include <sqlite3.h>

#include <algorithm>
#include <cctype>

#include "auth.h"
#include "core/ascii.h"
#include "core/errors.h"
#include "io/parse_json.h"
#include "sqlite_stmt.h"

namespace cgview::server {

using nlohmann::json;

namespace {

constexpr std::string_view kLinkPrefix = "cgl_";

std::int64_t unix_now() {
  return std::chrono::duration_cast<std::chrono::seconds>(std::chrono::system_clock::now().time_since_epoch()).count();
}

std::string trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return std::string(s);
}

// One CSV line's fields (RFC 4180's quotes, as Moodle's and Canvas's exports write them).
std::vector<std::string> csv_fields(std::string_view line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') out.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else out.back() += c;
    } else if (c == '"') quoted = true;
    else if (c == ',' || c == ';' || c == '\t') out.emplace_back();
    else out.back() += c;
  }
  for (auto& f : out) f = trim(f);
  return out;
}

struct RosterEntry {
  std::string login, name, role;
};

// The roster's entries; throws InvalidInput naming the first bad one.
std::vector<RosterEntry> parse_roster(std::string_view body, bool csv) {
  std::vector<RosterEntry> out;
  auto check = [&](RosterEntry e, const std::string& where) {
    if (!valid_user_name(e.login))
      throw InvalidInput(where + ": '" + e.login + "' is not a login (1 to 64 letters, digits, '_', '.' or '-')");
    if (e.role.empty()) e.role = "student";
    if (e.role != "student" && e.role != "assistant" && e.role != "teacher")
      throw InvalidInput(where + ": role '" + e.role + "' is not student, assistant or teacher");
    if (e.name.size() > 200) throw InvalidInput(where + ": the name is over 200 characters");
    out.push_back(std::move(e));
  };
  if (csv) {
    std::size_t line_no = 0, pos = 0;
    while (pos <= body.size()) {
      const std::size_t end = std::min(body.find('\n', pos), body.size());
      const std::string line = trim(body.substr(pos, end - pos));
      pos = end + 1;
      ++line_no;
      if (line.empty()) continue;
      const auto f = csv_fields(line);
      const std::string first = ascii_lower(f[0]);
      if (line_no == 1 && (first == "login" || first == "username" || first == "user" || first == "email")) continue;
      check({f[0], f.size() > 1 ? f[1] : "", f.size() > 2 ? ascii_lower(f[2]) : ""}, "line " + std::to_string(line_no));
    }
  } else {
    const json j = parse_json_or_discarded(body);
    const json& list = j.is_object() ? j.value("members", json()) : j;
    if (!list.is_array())
      throw InvalidInput("the body is a JSON list of {\"login\", \"name\", \"role\"} (or {\"members\": [...]}) or CSV");
    std::size_t i = 0;
    for (const json& m : list) {
      const std::string where = "member " + std::to_string(i++);
      if (m.is_string()) check({m.get<std::string>(), "", ""}, where);
      else if (m.is_object() && m.value("login", json()).is_string() && m.value("name", json("")).is_string() &&
               m.value("role", json("")).is_string())
        check({m["login"], m.value("name", ""), m.value("role", "")}, where);
      else throw InvalidInput(where + ": {\"login\": NAME, \"name\": \"Full Name\", \"role\": \"student\"}");
    }
  }
  if (out.size() > Courses::kMaxRoster)
    throw InvalidInput("a roster of " + std::to_string(out.size()) + " members: at most " +
                       std::to_string(Courses::kMaxRoster) + " a request");
  return out;
}

void check_link_life(std::chrono::seconds life) {
  if (life.count() < 60 || life > Courses::kMaxLinkLife)
    throw InvalidInput("a sign-in link lives 60 s to a week (" + std::to_string(Courses::kMaxLinkLife.count()) + " s)");
}

}  // namespace

Courses::Courses(Store& store, std::function<std::int64_t()> now)
    : store_(store), now_(now ? std::move(now) : unix_now) {
  db_ = open_database(store.data_dir() / "cgview.db");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS courses (id TEXT PRIMARY KEY, title TEXT NOT NULL, join_code TEXT NOT NULL,"
           " created TEXT NOT NULL, created_by TEXT NOT NULL);"
           "CREATE TABLE IF NOT EXISTS course_members (course TEXT NOT NULL, user TEXT NOT NULL, role TEXT NOT NULL,"
           " name TEXT NOT NULL, added TEXT NOT NULL, PRIMARY KEY (course, user));"
           "CREATE INDEX IF NOT EXISTS course_members_user ON course_members(user);"
           "CREATE TABLE IF NOT EXISTS course_links (id TEXT PRIMARY KEY, hash TEXT NOT NULL, course TEXT NOT NULL,"
           " user TEXT NOT NULL, expires INTEGER NOT NULL);",
           "courses");
}

Courses::~Courses() { sqlite3_close(db_); }

std::optional<std::string> Courses::role_locked(const std::string& course, const Caller& caller) const {
  Stmt s(db_, "SELECT role FROM course_members WHERE course = ?1 AND user = ?2");
  s.bind(1, course).bind(2, caller.user);
  if (s.step()) return s.text(0);
  if (caller.admin) {
    Stmt c(db_, "SELECT 1 FROM courses WHERE id = ?1");
    c.bind(1, course);
    if (c.step()) return "teacher";
  }
  return std::nullopt;
}

std::optional<std::string> Courses::role(const std::string& course, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  return role_locked(course, caller);
}

std::string Courses::require_member(const std::string& course, const Caller& caller) const {
  const auto r = role(course, caller);
  if (!r) throw std::out_of_range("no course with id '" + course + "'");
  return *r;
}

void Courses::require_staff(const std::string& course, const Caller& caller, bool teacher_only) const {
  const std::string r = require_member(course, caller);
  if (r == "teacher" || (!teacher_only && r == "assistant")) return;
  throw Forbidden(teacher_only ? "only a teacher of course " + course + " changes it"
                               : "only the staff of course " + course + " (teachers, assistants) see this");
}

json Courses::create(const json& body, const Caller& caller) {
  if (!caller.teacher && !caller.admin)
    throw Forbidden(
        "only a teacher creates courses (the admin gives the role: cgview-server user add NAME --role teacher)");
  if (!body.is_object() || !body.value("title", json()).is_string() || body["title"].get<std::string>().empty() ||
      body["title"].get<std::string>().size() > 200)
    throw InvalidInput("the body is {\"title\": \"Geometry Processing 2027\"} (1 to 200 characters)");
  const std::string id = new_id(), now = now_iso8601();
  std::lock_guard lock(mutex_);
  exec_sql(db_, "BEGIN IMMEDIATE", "courses");
  try {
    Stmt c(db_, "INSERT INTO courses (id, title, join_code, created, created_by) VALUES (?1, ?2, ?3, ?4, ?5)");
    c.bind(1, id).bind(2, body["title"].get<std::string>()).bind(3, random_hex(5)).bind(4, now).bind(5, caller.user);
    c.step();
    Stmt m(db_, "INSERT INTO course_members (course, user, role, name, added) VALUES (?1, ?2, 'teacher', '', ?3)");
    m.bind(1, id).bind(2, caller.user).bind(3, now);
    m.step();
    exec_sql(db_, "COMMIT", "courses");
  } catch (...) {
    exec_sql(db_, "ROLLBACK", "courses");
    throw;
  }
  return {{"id", id}, {"title", body["title"]}, {"role", "teacher"}, {"created", now}};
}

json Courses::list(const Caller& caller) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_,
         "SELECT c.id, c.title, c.created, IFNULL(m.role, 'teacher') FROM courses c LEFT JOIN course_members m"
         " ON m.course = c.id AND m.user = ?1 WHERE m.user IS NOT NULL OR ?2 ORDER BY c.created, c.id");
  s.bind(1, caller.user).bind(2, std::int64_t(caller.admin));
  json out = json::array();
  while (s.step())
    out.push_back({{"id", s.text(0)}, {"title", s.text(1)}, {"created", s.text(2)}, {"role", s.text(3)}});
  return out;
}

json Courses::members_json(const std::string& course) const {
  Stmt s(db_, "SELECT user, name, role, added FROM course_members WHERE course = ?1 ORDER BY role DESC, user");
  s.bind(1, course);
  json out = json::array();
  while (s.step())
    out.push_back({{"login", s.text(0)}, {"name", s.text(1)}, {"role", s.text(2)}, {"added", s.text(3)}});
  return out;
}

json Courses::get(const std::string& course, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  const auto r = role_locked(course, caller);
  if (!r) throw std::out_of_range("no course with id '" + course + "'");
  Stmt s(db_, "SELECT title, created, join_code FROM courses WHERE id = ?1");
  s.bind(1, course);
  s.step();
  json out = {{"id", course}, {"title", s.text(0)}, {"created", s.text(1)}, {"role", *r}};
  if (*r != "student") out["members"] = members_json(course);
  if (*r == "teacher") out["join_code"] = s.text(2);
  return out;
}

std::string Courses::add_link(const std::string& course, const std::string& user, std::chrono::seconds life) {
  const std::string id = random_hex(8), secret = random_hex(32);
  Stmt s(db_, "INSERT INTO course_links (id, hash, course, user, expires) VALUES (?1, ?2, ?3, ?4, ?5)");
  s.bind(1, id).bind(2, sha256_hex(secret)).bind(3, course).bind(4, user).bind(5, now_() + life.count());
  s.step();
  return std::string(kLinkPrefix) + id + "_" + secret;
}

json Courses::add_members(const std::string& course, std::string_view body, bool csv, std::chrono::seconds link_life,
                          const Caller& caller) {
  require_staff(course, caller, true);
  check_link_life(link_life);
  const auto roster = parse_roster(body, csv);
  // The accounts first, through the store's own connection (it would wait
  // on this one's transaction); the roster was checked whole before.
  std::vector<bool> is_new;
  for (const RosterEntry& e : roster) is_new.push_back(store_.ensure_user(e.login));
  json created = json::array(), links = json::array();
  std::lock_guard lock(mutex_);
  // One transaction: the members are enrolled together or not at all.
  exec_sql(db_, "BEGIN IMMEDIATE", "courses");
  try {
    for (std::size_t i = 0; i < roster.size(); ++i) {
      const RosterEntry& e = roster[i];
      Stmt m(db_,
             "INSERT INTO course_members (course, user, role, name, added) VALUES (?1, ?2, ?3, ?4, ?5)"
             " ON CONFLICT(course, user) DO UPDATE SET role = excluded.role,"
             " name = CASE WHEN excluded.name = '' THEN name ELSE excluded.name END");
      m.bind(1, course).bind(2, e.login).bind(3, e.role).bind(4, e.name).bind(5, now_iso8601());
      m.step();
      if (!is_new[i]) continue;
      created.push_back(e.login);
      links.push_back(
          {{"user", e.login}, {"ticket", add_link(course, e.login, link_life)}, {"expires_s", link_life.count()}});
    }
    exec_sql(db_, "COMMIT", "courses");
  } catch (...) {
    exec_sql(db_, "ROLLBACK", "courses");
    throw;
  }
  return {{"members", members_json(course)}, {"created", created}, {"links", links}};
}

json Courses::new_link(const std::string& course, const std::string& user, std::chrono::seconds link_life,
                       const Caller& caller) {
  require_staff(course, caller, true);
  check_link_life(link_life);
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT 1 FROM course_members WHERE course = ?1 AND user = ?2");
  s.bind(1, course).bind(2, user);
  if (!s.step()) throw std::out_of_range("no member '" + user + "' in course " + course);
  return {{"user", user}, {"ticket", add_link(course, user, link_life)}, {"expires_s", link_life.count()}};
}

void Courses::remove_member(const std::string& course, const std::string& user, const Caller& caller) {
  require_staff(course, caller, true);
  std::lock_guard lock(mutex_);
  Stmt r(db_,
         "SELECT role, (SELECT COUNT(*) FROM course_members WHERE course = ?1 AND role = 'teacher')"
         " FROM course_members WHERE course = ?1 AND user = ?2");
  r.bind(1, course).bind(2, user);
  if (!r.step()) throw std::out_of_range("no member '" + user + "' in course " + course);
  if (r.text(0) == "teacher" && r.integer(1) <= 1) throw InvalidInput("the last teacher of a course stays in it");
  Stmt d(db_, "DELETE FROM course_members WHERE course = ?1 AND user = ?2");
  d.bind(1, course).bind(2, user);
  d.step();
  // Their links to this course go with them.
  Stmt l(db_, "DELETE FROM course_links WHERE course = ?1 AND user = ?2");
  l.bind(1, course).bind(2, user);
  l.step();
}

std::optional<json> Courses::join(const std::string& code, const Caller& caller) {
  if (caller.user == "local" || code.empty()) return std::nullopt;
  std::lock_guard lock(mutex_);
  Stmt c(db_, "SELECT id, title FROM courses WHERE join_code = ?1");
  c.bind(1, code);
  if (!c.step()) return std::nullopt;
  const std::string id = c.text(0);
  Stmt m(db_,
         "INSERT OR IGNORE INTO course_members (course, user, role, name, added) VALUES (?1, ?2, 'student', '', ?3)");
  m.bind(1, id).bind(2, caller.user).bind(3, now_iso8601());
  m.step();
  return json{{"id", id}, {"title", c.text(1)}, {"role", role_locked(id, caller).value_or("student")}};
}

std::optional<std::string> Courses::redeem_link(std::string_view link) {
  // cgl_ + 16 hex + _ + 64 hex
  if (link.size() != kLinkPrefix.size() + 16 + 1 + 64 || !link.starts_with(kLinkPrefix) ||
      link[kLinkPrefix.size() + 16] != '_')
    return std::nullopt;
  const std::string id(link.substr(kLinkPrefix.size(), 16));
  const std::string_view secret = link.substr(kLinkPrefix.size() + 17);
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT hash, user, expires FROM course_links WHERE id = ?1");
  s.bind(1, id);
  if (!s.step()) return std::nullopt;
  const std::string hash = s.text(0), user = s.text(1);
  const std::int64_t expires = s.integer(2);
  if (!same_digest(hash, sha256_hex(secret))) return std::nullopt;
  // Used once, right or late.
  Stmt d(db_, "DELETE FROM course_links WHERE id = ?1");
  d.bind(1, id);
  d.step();
  if (now_() >= expires) return std::nullopt;
  return user;
}

std::vector<std::string> Courses::groups_of(const std::string& user) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT course, role FROM course_members WHERE user = ?1");
  s.bind(1, user);
  std::vector<std::string> out;
  while (s.step()) {
    out.push_back(group(s.text(0)));
    if (s.text(1) != "student") out.push_back(staff(s.text(0)));
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> Courses::students(const std::string& course) const {
  std::lock_guard lock(mutex_);
  Stmt s(db_, "SELECT user, name FROM course_members WHERE course = ?1 AND role = 'student' ORDER BY user");
  s.bind(1, course);
  std::vector<std::pair<std::string, std::string>> out;
  while (s.step()) out.emplace_back(s.text(0), s.text(1));
  return out;
}

}  // namespace cgview::server
