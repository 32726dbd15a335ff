// Sign-in tickets: how a page that must not be given a token in its URL (the
// viewer in a notebook's output cell, on a server off loopback) signs in.
// A token's holder asks for a ticket, "cgt_ID_SECRET", that lives a minute
// and is redeemed once, by the page, for a session credential of the same
// user that expires, "cgv_ID_SECRET" (the shape of a token, so that every
// place that takes a token takes it).  As for tokens, only the SHA-256 of a
// secret is kept, and only in memory: a restart ends every ticket and
// session.  A session stands for the token it was made from: revoking that
// token ends it (Auth checks the token at each use).
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace cgview::server {

class Tickets {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::chrono::seconds kTicketLife{60};
  static constexpr std::chrono::seconds kSessionLife{8 * 3600};
  // Live tickets and sessions kept at most; past it the one nearest its end goes first.
  static constexpr std::size_t kMaxEntries = 100000;

  // now: the clock (tests move it).
  explicit Tickets(std::function<Clock::time_point()> now = Clock::now) : now_(std::move(now)) {}

  // Whom a ticket or session stands for: a user, through one of their tokens (its id).
  struct Grant {
    std::string user;
    std::string token_id;
  };
  struct Session {
    std::string token;  // "cgv_ID_SECRET"
    Grant grant;
    std::chrono::seconds life;
  };

  // A new ticket for `grant`, redeemable once within `life` (clamped to 1 s..kTicketLife).
  std::string issue(const Grant& grant, std::chrono::seconds life = kTicketLife);
  // A new session for a ticket, which is gone once tried; nullopt when the
  // ticket is malformed, forged, used or expired.
  std::optional<Session> redeem(std::string_view ticket);
  // The grant of a live session "cgv_ID_SECRET", given its ID and SECRET;
  // nullopt when none has that ID, the secret is wrong or it expired.
  std::optional<Grant> session(std::string_view id, std::string_view secret) const;
  // Replaces the clock (tests).
  void set_clock(std::function<Clock::time_point()> now) {
    std::lock_guard lock(mutex_);
    now_ = std::move(now);
  }

 private:
  struct Entry {
    std::string hash;  // SHA-256 of the secret, hex
    Grant grant;
    Clock::time_point expires;
  };
  using Entries = std::unordered_map<std::string, Entry>;
  // Adds a new entry to `entries`; its credential "PREFIXID_SECRET".
  std::string add(Entries& entries, std::string_view prefix, const Grant& grant, std::chrono::seconds life);
  void purge(Clock::time_point now);

  std::function<Clock::time_point()> now_;
  mutable std::mutex mutex_;
  Entries tickets_, sessions_;
};

}  // namespace cgview::server
