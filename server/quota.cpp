#include "quota.h"

#include <cstdio>

namespace cgview::server {

UserLimits QuotaConfig::limits(const Caller& caller) const {
  // The local user and admins are unlimited by default: only their own entry binds them.
  UserLimits l = caller.admin ? UserLimits{} : defaults;
  if (const auto it = users.find(caller.user); it != users.end()) {
    if (it->second.storage_bytes) l.storage_bytes = *it->second.storage_bytes;
    if (it->second.concurrent_jobs) l.concurrent_jobs = *it->second.concurrent_jobs;
    if (it->second.plugins) l.plugins = *it->second.plugins;
  }
  return l;
}

std::string format_bytes(std::uint64_t bytes) {
  char buf[64];
  if (bytes < 1024) std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  else if (bytes < (std::uint64_t(1) << 20)) std::snprintf(buf, sizeof buf, "%.1f KB", double(bytes) / 1024);
  else if (bytes < (std::uint64_t(1) << 30)) std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / (1 << 20));
  else std::snprintf(buf, sizeof buf, "%.2f GB", double(bytes) / (1 << 30));
  return buf;
}

namespace {

std::string storage_text(const UserLimits& l, const Usage& u) {
  return "storage quota of " + format_bytes(*l.storage_bytes) + " exceeded: " + format_bytes(u.storage_bytes) + " used";
}

}  // namespace

void check_storage(const UserLimits& l, const Usage& u, std::uint64_t adding, const std::string& what) {
  if (!l.storage_bytes || u.storage_bytes + adding <= *l.storage_bytes) return;
  throw QuotaExceeded(413, "storage_quota", storage_text(l, u) + ", " + what + " is " + format_bytes(adding),
                      *l.storage_bytes, u.storage_bytes);
}

std::uint64_t room_left(const UserLimits& l, const Usage& u) {
  if (!l.storage_bytes) return ~std::uint64_t(0);
  return u.storage_bytes < *l.storage_bytes ? *l.storage_bytes - u.storage_bytes : 0;
}

void check_room_for_results(const UserLimits& l, const Usage& u) {
  if (room_left(l, u) > 0) return;
  throw QuotaExceeded(413, "storage_quota", storage_text(l, u) + ", no room is left for a job's results",
                      *l.storage_bytes, u.storage_bytes);
}

void check_jobs(const UserLimits& l, const Usage& u) {
  if (!l.concurrent_jobs || u.jobs_active < *l.concurrent_jobs) return;
  throw QuotaExceeded(429, "job_limit",
                      "concurrent job limit of " + std::to_string(*l.concurrent_jobs) + " reached: " +
                          std::to_string(u.jobs_active) + " queued or running; submit again when one ends",
                      std::uint64_t(*l.concurrent_jobs), std::uint64_t(u.jobs_active));
}

}  // namespace cgview::server
