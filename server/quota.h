// Per-user quotas: a storage limit (the bytes of the meshes a user owns and
// of their jobs' artifacts) and a cap on the jobs a user has queued or
// running at once.  Defaults come from the server's config file (config.h),
// with per-user overrides there too; the local user and admins are
// unlimited unless the file names them.  Over a limit a request gets 413
// (storage) or 429 (jobs, with Retry-After), its message naming the limit
// and the current use.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>

#include "store.h"

namespace cgview::server {

// One user's limits; nullopt: none.
struct UserLimits {
  std::optional<std::uint64_t> storage_bytes;
  std::optional<int> concurrent_jobs;
  bool plugins = true;  // may build and run plugins (where the server sandboxes them)
};

// A user's own limits: each field given (the outer optional) replaces the
// default; nullopt inside means unlimited.
struct UserOverride {
  std::optional<std::optional<std::uint64_t>> storage_bytes;
  std::optional<std::optional<int>> concurrent_jobs;
  std::optional<bool> plugins;
};

struct QuotaConfig {
  UserLimits defaults;                        // every user but the local one and admins
  std::map<std::string, UserOverride> users;  // by name (the local user is "local")
  // The limits that hold for a caller.
  UserLimits limits(const Caller& caller) const;
};

// What a user uses now.
struct Usage {
  std::uint64_t storage_bytes = 0;
  int jobs_active = 0;  // queued or running
};

// A request over a limit: status 413 (storage_quota) or 429 (job_limit).
struct QuotaExceeded : std::runtime_error {
  QuotaExceeded(int status_, std::string code_, const std::string& detail, std::uint64_t limit_, std::uint64_t used_)
      : std::runtime_error(detail), status(status_), code(std::move(code_)), limit(limit_), used(used_) {}
  int status;
  std::string code;
  std::uint64_t limit, used;
  int retry_after_s = 10;  // for 429
};

// Throws QuotaExceeded (413) when `adding` more bytes take the caller over
// their storage limit; `what` names them ("this upload").
void check_storage(const UserLimits& limits, const Usage& usage, std::uint64_t adding, const std::string& what);
// The bytes left under the storage limit (none when at or over it; the
// most there is where there is no limit).
std::uint64_t room_left(const UserLimits& limits, const Usage& usage);
// Throws QuotaExceeded (413) when the caller has no room left for a job's
// results (at or over their storage limit).
void check_room_for_results(const UserLimits& limits, const Usage& usage);
// Throws QuotaExceeded (429) when the caller already has their limit of
// queued and running jobs.
void check_jobs(const UserLimits& limits, const Usage& usage);

// "498.2 MB", "12.0 KB", "512 bytes" (binary units, as --max-upload-mb).
std::string format_bytes(std::uint64_t bytes);

}  // namespace cgview::server
