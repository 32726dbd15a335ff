// Courses: a class of users with roles, and what is shared with it.
//
// A teacher (Role::teacher, or an admin) creates a course and is its first
// teacher.  Members have a role in it: teacher (everything, its settings
// included), assistant (the teacher's view without the settings) or
// student.  A course is a pair of groups (Caller::groups): "course:ID",
// every member, and "staff:ID", its teachers and assistants; an item
// shared with a group is read by its members, read-only, and removing a
// member ends that at their next request, since a caller's groups are read
// at each one.
//
// Enrolment: a roster (logins and names, JSON or CSV) makes the accounts
// that are missing and gives each new student a one-time sign-in link
// ("cgl_ID_SECRET", redeemed at POST /api/v1/tickets/redeem for a token of
// the student's own) with a lifetime the teacher chooses, up to a week; a
// course's join code lets a signed-in user join as a student.  As for
// tokens, only the SHA-256 of a link's secret is stored, in the data
// directory's database, so that links outlive a restart.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "store.h"

struct sqlite3;

namespace cgview::server {

class Courses {
 public:
  static constexpr std::chrono::seconds kMaxLinkLife{7 * 24 * 3600};
  static constexpr std::chrono::seconds kDefaultLinkLife{3 * 24 * 3600};
  static constexpr std::size_t kMaxRoster = 2000;  // members added by one request

  // now: the clock, in seconds since the epoch (tests move it).
  explicit Courses(Store& store, std::function<std::int64_t()> now = nullptr);
  ~Courses();
  Courses(const Courses&) = delete;
  Courses& operator=(const Courses&) = delete;

  // A member's role in a course: "teacher", "assistant" or "student"; an
  // admin is a teacher of every course.  nullopt: not a member (an unknown
  // course answers the same).
  std::optional<std::string> role(const std::string& course, const Caller& caller) const;
  // Throws std::out_of_range (404) unless the caller is a member; Forbidden
  // unless they are staff (teacher or assistant) or, with teacher_only, a teacher.
  std::string require_member(const std::string& course, const Caller& caller) const;
  void require_staff(const std::string& course, const Caller& caller, bool teacher_only = false) const;

  // POST /api/v1/courses {"title"}: Forbidden unless the caller is a teacher or an admin.
  nlohmann::json create(const nlohmann::json& body, const Caller& caller);
  // The courses the caller is in (an admin: all), with their role in each.
  nlohmann::json list(const Caller& caller) const;
  // One course: its title and the caller's role; staff also see its members,
  // a teacher its join code.
  nlohmann::json get(const std::string& course, const Caller& caller) const;
  // Adds members from a roster (a teacher): `body` is a JSON list of
  // {"login", "name"?, "role"?} or CSV text ("login,name[,role]", a header
  // line optional), `link_life` how long the sign-in links live.  Returns
  // {"members", "created", "links": [{"user", "ticket", "expires"}]}.
  // Throws InvalidInput naming the first bad line.
  nlohmann::json add_members(const std::string& course, std::string_view body, bool csv, std::chrono::seconds link_life,
                             const Caller& caller);
  // A new sign-in link for a member (a teacher), as add_members gives them.
  nlohmann::json new_link(const std::string& course, const std::string& user, std::chrono::seconds link_life,
                          const Caller& caller);
  // Removes a member (a teacher); the last teacher stays.
  void remove_member(const std::string& course, const std::string& user, const Caller& caller);
  // A signed-in user joins as a student with the course's join code;
  // nullopt for a wrong code.
  std::optional<nlohmann::json> join(const std::string& code, const Caller& caller);
  // The user a link stands for, once: nullopt when it is malformed, forged,
  // used or expired.
  std::optional<std::string> redeem_link(std::string_view link);
  // Caller::groups of a user.
  std::vector<std::string> groups_of(const std::string& user) const;
  // The logins of a course's students (grades list them all, submitted or not).
  std::vector<std::pair<std::string, std::string>> students(const std::string& course) const;  // login, name
  // "course:ID" and "staff:ID".
  static std::string group(const std::string& course) { return "course:" + course; }
  static std::string staff(const std::string& course) { return "staff:" + course; }

 private:
  nlohmann::json members_json(const std::string& course) const;  // under mutex_
  std::string add_link(const std::string& course, const std::string& user, std::chrono::seconds life);
  std::optional<std::string> role_locked(const std::string& course, const Caller& caller) const;

  Store& store_;
  std::function<std::int64_t()> now_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
};

}  // namespace cgview::server
