// The queue of jobs waiting for an executor, fair across owners: each owner
// has a queue of their own, and the next job comes from the owner after the
// one served last (round-robin), so one user's hundred jobs never hold back
// another's first.
#pragma once

#include <cstddef>
#include <deque>
#include <map>
#include <optional>
#include <string>

namespace cgview::server {

class FairQueue {
 public:
  void push(const std::string& owner, const std::string& id);
  // Removes a queued job; false when it was not queued.
  bool remove(const std::string& owner, const std::string& id);
  // The next job in turn, taken out of the queue; nullopt when empty.
  std::optional<std::string> pop();
  std::size_t size() const { return size_; }

 private:
  std::map<std::string, std::deque<std::string>> queues_;  // by owner; no empty queue kept
  std::string last_owner_;
  std::size_t size_ = 0;
};

}  // namespace cgview::server
