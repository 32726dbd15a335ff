#include "rate_limit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "auth.h"

namespace cgview::server {

std::optional<double> RateLimiter::take(const std::string& key, Clock::time_point now) {
  if (!enabled() || key.empty()) return std::nullopt;
  std::lock_guard lock(mutex_);
  // Full buckets carry no state: dropped now and then, so that a client
  // inventing tokens or addresses cannot grow the map without bound.
  if (buckets_.size() > 10000)
    std::erase_if(buckets_, [&](const auto& kv) {
      return kv.second.tokens + std::chrono::duration<double>(now - kv.second.at).count() * rate_ >= burst_;
    });
  auto [it, fresh] = buckets_.try_emplace(key, Bucket{burst_, now});
  Bucket& b = it->second;
  if (!fresh) {
    b.tokens = std::min(burst_, b.tokens + std::chrono::duration<double>(now - b.at).count() * rate_);
    b.at = std::max(b.at, now);
  }
  if (b.tokens >= 1) {
    b.tokens -= 1;
    return std::nullopt;
  }
  return (1 - b.tokens) / rate_;
}

std::string RateLimiter::describe() const {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%g requests per second, bursts of %g", rate_, burst_);
  return buf;
}

std::string rate_key(std::string_view authorization, const std::string& address, bool loopback) {
  constexpr std::string_view bearer = "bearer cgv_";
  if (authorization.size() > bearer.size() + 16 && starts_with_nocase(authorization, bearer))
    return "token:" + std::string(authorization.substr(bearer.size(), 16));
  if (authorization.empty() && loopback) return {};
  return "ip:" + address;
}

std::optional<RateRefusal> check_rate(RateLimiter& limiter, std::string_view authorization, const std::string& address,
                                      bool loopback) {
  const std::string key = rate_key(authorization, address, loopback);
  const auto wait = limiter.take(key);
  if (!wait) return std::nullopt;
  if (limiter.on_refused) limiter.on_refused();
  const int retry = int(std::max(1.0, std::ceil(*wait)));
  return RateRefusal{retry, "over the rate limit of " + limiter.describe() + " for this " +
                                (key.starts_with("token:") ? "token" : "address") + "; retry after " +
                                std::to_string(retry) + " s"};
}

}  // namespace cgview::server
