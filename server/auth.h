// Users and bearer tokens.  A token is "cgv_ID_SECRET": ID (16 hex digits)
// names the stored row, SECRET is 256 random bits from OpenSSL's CSPRNG
// (64 hex digits) of which only the SHA-256 is stored; a token is checked by
// hashing its secret and comparing the hashes in constant time.  Tokens are
// never logged.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "store.h"
#include "tickets.h"

namespace cgview::server {

// What a user may do beyond their own data: create courses (teacher), or see and change everyone's (admin).
enum class Role { user, teacher, admin };
// "user", "teacher" or "admin"; nullopt for anything else.
std::optional<Role> role_from(std::string_view name);

class Auth {
 public:
  // required: every request needs a token; else one without a token is
  // Caller::local() (a loopback server's single user).
  Auth(Store& store, bool required) : store_(store), required_(required), tickets_(std::make_unique<Tickets>()) {}

  bool required() const { return required_; }
  // The caller of a request from its Authorization header ("Bearer TOKEN",
  // or empty); nullopt answers 401: no header where one is required, or a
  // wrong or revoked token (even where none is required).
  std::optional<Caller> authenticate(std::string_view authorization) const;

  // Creates the user if needed (or changes their role) and returns a new token.
  std::string add_user(const std::string& name, Role role);
  std::string add_user(const std::string& name, bool admin) { return add_user(name, admin ? Role::admin : Role::user); }
  // A new token of an existing user (a course's sign-in link redeemed).
  std::string new_token(const std::string& user) const;
  // The groups of a user (Caller::groups), asked at each authentication;
  // set before the server serves.
  void set_groups(std::function<std::vector<std::string>(const std::string& user)> groups) {
    groups_ = std::move(groups);
  }

  // Sign-in tickets (tickets.h).  A ticket for the token of `authorization`
  // ("Bearer TOKEN", already authenticated), redeemable once within `life`;
  // nullopt when it names no stored token: none given (the local user), or a
  // session's (a session makes no tickets, so that it cannot outlive its end).
  std::optional<std::string> issue_ticket(std::string_view authorization,
                                          std::chrono::seconds life = Tickets::kTicketLife) const;
  // A session for a ticket; nullopt when the ticket is forged, used or
  // expired, or its token was revoked since.
  std::optional<Tickets::Session> redeem_ticket(std::string_view ticket) const;
  // Replaces the tickets' clock (tests).
  void set_ticket_clock(std::function<Tickets::Clock::time_point()> now) const { tickets_->set_clock(std::move(now)); }

 private:
  std::optional<Caller> check_token(std::string_view token) const;
  // The caller of a stored token's id, if the token still is (not revoked) and is `user`'s.
  std::optional<Caller> token_caller(const std::string& token_id, const std::string* user = nullptr) const;
  Store& store_;
  bool required_;
  std::function<std::vector<std::string>(const std::string&)> groups_;
  // Tickets and sessions change while Auth is used read-only (by the router, the WebSockets).
  std::unique_ptr<Tickets> tickets_;
};

// True when s begins with prefix, ASCII case ignored (an HTTP auth scheme).
bool starts_with_nocase(std::string_view s, std::string_view prefix);

// `bytes` random bytes from OpenSSL's CSPRNG, as hex.
std::string random_hex(std::size_t bytes);
// Whether two digests (hex) are equal, compared in constant time; false when empty.
bool same_digest(std::string_view a, std::string_view b);

// True for a user name: 1..64 of [A-Za-z0-9_.-], not "local" or "system".
bool valid_user_name(const std::string& name);

}  // namespace cgview::server
