#include "auth.h"

#include <openssl/crypto.h>
#include <openssl/rand.h>

#include <cctype>
#include <vector>

#include "core/errors.h"

namespace cgview::server {

namespace {

constexpr std::string_view kPrefix = "cgv_";

}  // namespace

std::string random_hex(std::size_t bytes) {
  std::vector<unsigned char> raw(bytes);
  if (RAND_bytes(raw.data(), int(bytes)) != 1) throw Error("no random bytes from OpenSSL");
  return to_hex(raw.data(), bytes);
}

bool same_digest(std::string_view a, std::string_view b) {
  return a.size() == b.size() && !a.empty() && CRYPTO_memcmp(a.data(), b.data(), a.size()) == 0;
}

bool starts_with_nocase(std::string_view s, std::string_view prefix) {
  if (s.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(s[i])) != std::tolower(static_cast<unsigned char>(prefix[i])))
      return false;
  return true;
}

bool valid_user_name(const std::string& name) {
  if (name.empty() || name.size() > 64 || name == "local" || name == kSystemOwner) return false;
  for (unsigned char c : name)
    if (!std::isalnum(c) && c != '_' && c != '.' && c != '-') return false;
  return true;
}

std::optional<Caller> Auth::authenticate(std::string_view authorization) const {
  if (authorization.empty()) return required_ ? std::nullopt : std::optional(Caller::local());
  constexpr std::string_view bearer = "Bearer ";
  // the scheme is case-insensitive (RFC 7235)
  if (authorization.size() <= bearer.size() || !starts_with_nocase(authorization, bearer)) return std::nullopt;
  return check_token(authorization.substr(bearer.size()));
}

std::optional<Caller> Auth::check_token(std::string_view token) const {
  // cgv_ + 16 hex + _ + 64 hex
  if (token.size() != kPrefix.size() + 16 + 1 + 64 || !token.starts_with(kPrefix) || token[kPrefix.size() + 16] != '_')
    return std::nullopt;
  const std::string id(token.substr(kPrefix.size(), 16));
  const std::string_view secret = token.substr(kPrefix.size() + 17);
  // A session (a redeemed ticket) stands for its token while that token is not revoked.
  if (const auto grant = tickets_->session(id, secret)) return token_caller(grant->token_id, &grant->user);
  const auto row = store_.find_token(id);
  if (!row) return std::nullopt;
  if (!same_digest(row->second, sha256_hex(secret))) return std::nullopt;
  return token_caller(id);
}

std::optional<Caller> Auth::token_caller(const std::string& token_id, const std::string* user) const {
  const auto row = store_.find_token(token_id);
  if (!row || (user && row->first != *user)) return std::nullopt;
  const auto record = store_.get_user(row->first);
  if (!record) return std::nullopt;
  Caller c{record->name, record->admin, record->teacher};
  if (groups_) c.groups = groups_(c.user);
  return c;
}

std::optional<std::string> Auth::issue_ticket(std::string_view authorization, std::chrono::seconds life) const {
  constexpr std::string_view bearer = "Bearer ";
  if (authorization.size() <= bearer.size() || !starts_with_nocase(authorization, bearer)) return std::nullopt;
  const std::string_view token = authorization.substr(bearer.size());
  if (token.size() != kPrefix.size() + 16 + 1 + 64 || !token.starts_with(kPrefix)) return std::nullopt;
  const std::string id(token.substr(kPrefix.size(), 16));
  const auto row = store_.find_token(id);
  // Only a stored token makes tickets (the router has checked its secret); a session's id is not stored.
  if (!row || !same_digest(row->second, sha256_hex(token.substr(kPrefix.size() + 17)))) return std::nullopt;
  return tickets_->issue({row->first, id}, life);
}

std::optional<Tickets::Session> Auth::redeem_ticket(std::string_view ticket) const {
  auto session = tickets_->redeem(ticket);
  if (!session || !token_caller(session->grant.token_id, &session->grant.user)) return std::nullopt;
  return session;
}

std::optional<Role> role_from(std::string_view name) {
  if (name == "user") return Role::user;
  if (name == "teacher") return Role::teacher;
  if (name == "admin") return Role::admin;
  return std::nullopt;
}

std::string Auth::add_user(const std::string& name, Role role) {
  if (!valid_user_name(name))
    throw InvalidInput("'" + name +
                       "' is not a user name: 1 to 64 letters, digits, '_', '.' or '-' (not local or system)");
  store_.add_user(name, role == Role::admin, role == Role::teacher);
  return new_token(name);
}

std::string Auth::new_token(const std::string& name) const {
  const std::string id = random_hex(8), secret = random_hex(32);
  store_.add_token(id, name, sha256_hex(secret));
  return std::string(kPrefix) + id + "_" + secret;
}

}  // namespace cgview::server
