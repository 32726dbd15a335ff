#include "tickets.h"

#include <algorithm>

#include "auth.h"   // random_hex, same_digest
#include "store.h"  // sha256_hex

namespace cgview::server {

namespace {

constexpr std::string_view kTicketPrefix = "cgt_", kSessionPrefix = "cgv_";
constexpr std::size_t kIdHex = 16, kSecretHex = 64;

// The ID and SECRET of "PREFIXID_SECRET"; nullopt for another shape.
std::optional<std::pair<std::string_view, std::string_view>> split(std::string_view credential,
                                                                   std::string_view prefix) {
  if (credential.size() != prefix.size() + kIdHex + 1 + kSecretHex || !credential.starts_with(prefix) ||
      credential[prefix.size() + kIdHex] != '_')
    return std::nullopt;
  return std::pair{credential.substr(prefix.size(), kIdHex), credential.substr(prefix.size() + kIdHex + 1)};
}

}  // namespace

std::string Tickets::add(Entries& entries, std::string_view prefix, const Grant& grant, std::chrono::seconds life) {
  const Clock::time_point now = now_();
  purge(now);
  if (tickets_.size() + sessions_.size() >= kMaxEntries) {
    auto& from = tickets_.empty() ? sessions_ : tickets_;
    from.erase(std::min_element(from.begin(), from.end(),
                                [](const auto& a, const auto& b) { return a.second.expires < b.second.expires; }));
  }
  std::string id = random_hex(kIdHex / 2);
  while (entries.contains(id)) id = random_hex(kIdHex / 2);
  const std::string secret = random_hex(kSecretHex / 2);
  entries[id] = Entry{sha256_hex(secret), grant, now + life};
  return std::string(prefix) + id + "_" + secret;
}

void Tickets::purge(Clock::time_point now) {
  for (Entries* entries : {&tickets_, &sessions_})
    std::erase_if(*entries, [now](const auto& e) { return e.second.expires <= now; });
}

std::string Tickets::issue(const Grant& grant, std::chrono::seconds life) {
  std::lock_guard lock(mutex_);
  return add(tickets_, kTicketPrefix, grant, std::clamp(life, std::chrono::seconds(1), kTicketLife));
}

std::optional<Tickets::Session> Tickets::redeem(std::string_view ticket) {
  const auto parts = split(ticket, kTicketPrefix);
  if (!parts) return std::nullopt;
  std::lock_guard lock(mutex_);
  const auto it = tickets_.find(std::string(parts->first));
  if (it == tickets_.end()) return std::nullopt;
  const Entry entry = it->second;
  tickets_.erase(it);  // tried once, right or wrong: a ticket's secret is not guessed by trying
  if (entry.expires <= now_() || !same_digest(entry.hash, sha256_hex(parts->second))) return std::nullopt;
  return Session{add(sessions_, kSessionPrefix, entry.grant, kSessionLife), entry.grant, kSessionLife};
}

std::optional<Tickets::Grant> Tickets::session(std::string_view id, std::string_view secret) const {
  std::lock_guard lock(mutex_);
  const auto it = sessions_.find(std::string(id));
  if (it == sessions_.end() || it->second.expires <= now_() || !same_digest(it->second.hash, sha256_hex(secret)))
    return std::nullopt;
  return it->second.grant;
}

}  // namespace cgview::server
