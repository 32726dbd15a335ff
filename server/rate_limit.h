// Request rate limits: one token bucket per key (a bearer token's id, or a
// client address), of `burst` requests refilled at `rate` per second.  No
// Beast, no sockets: the sessions call it, tests drive it with their own clock.
#pragma once

#include <chrono>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>

namespace cgview::server {

class RateLimiter {
 public:
  using Clock = std::chrono::steady_clock;
  // rate <= 0: no limit (take() always admits).
  RateLimiter(double rate_per_s, double burst) : rate_(rate_per_s), burst_(std::max(1.0, burst)) {}

  bool enabled() const { return rate_ > 0; }
  // Takes one request from the key's bucket: nullopt when admitted, else
  // the seconds until one is (for Retry-After).  Thread-safe.
  std::optional<double> take(const std::string& key, Clock::time_point now = Clock::now());
  // "N requests per second, bursts of M" (the 429's detail).
  std::string describe() const;
  // Called for each refusal (the metrics count them).
  std::function<void()> on_refused;

 private:
  struct Bucket {
    double tokens;
    Clock::time_point at;
  };
  double rate_, burst_;
  std::mutex mutex_;
  std::unordered_map<std::string, Bucket> buckets_;
};

// The key of a request's bucket: "token:ID" for "Bearer cgv_ID_SECRET" (the
// id only: the secret is never kept), "ip:ADDRESS" for any other or no
// Authorization; empty (not limited) for a loopback client without one, the
// local user.
std::string rate_key(std::string_view authorization, const std::string& address, bool loopback);

// A request over its bucket's limit: what Retry-After says, and why.
struct RateRefusal {
  int retry_after_s = 1;
  std::string detail;
};

// Takes one request from the bucket of its token (or address): nullopt when
// admitted, else the refusal (429 over HTTP, an error message on a WebSocket).
std::optional<RateRefusal> check_rate(RateLimiter& limiter, std::string_view authorization, const std::string& address,
                                      bool loopback);

}  // namespace cgview::server
