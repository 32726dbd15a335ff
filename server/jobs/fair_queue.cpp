#include "jobs/fair_queue.h"

#include <algorithm>

namespace cgview::server {

void FairQueue::push(const std::string& owner, const std::string& id) {
  queues_[owner].push_back(id);
  ++size_;
}

bool FairQueue::remove(const std::string& owner, const std::string& id) {
  const auto it = queues_.find(owner);
  if (it == queues_.end()) return false;
  auto& q = it->second;
  const auto at = std::find(q.begin(), q.end(), id);
  if (at == q.end()) return false;
  q.erase(at);
  --size_;
  if (q.empty()) queues_.erase(it);
  return true;
}

std::optional<std::string> FairQueue::pop() {
  if (queues_.empty()) return std::nullopt;
  auto it = queues_.upper_bound(last_owner_);
  if (it == queues_.end()) it = queues_.begin();
  last_owner_ = it->first;
  std::string id = it->second.front();
  it->second.pop_front();
  --size_;
  if (it->second.empty()) queues_.erase(it);
  return id;
}

}  // namespace cgview::server
