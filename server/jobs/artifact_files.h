// A job's artifacts as its worker (or an upload's reader) left them in a
// directory it wrote: checked against the list it gave, then taken out
// into a directory of the server's, from which they are served ever after.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "jobs/job_files.h"

namespace cgview::server {

// Why a worker's artifact list does not match its files ("" when it does):
// at most kMaxArtifacts entries, each naming a plain regular file of the
// directory that is there (no link), a scalar field's file holds its count
// of floats, only text may be empty, each file has the size its worker
// wrote it with ("bytes"), and all together at most `max_bytes` (what
// the owner has left under their storage quota).
std::string incomplete_artifact(const JobDir& dir, const nlohmann::json& artifacts,
                                std::uint64_t max_bytes = ~std::uint64_t(0));

// Copies each artifact's file, and the side files its codec names, out of
// `work` into `to` (a fresh directory only the server writes), where the
// job's results are served from ever after; moves them instead where
// `whole` says nothing of the run writes any more (JobDir::move).  "" when
// all were taken, else why not (`to` is then removed).
std::string take_artifacts(const JobDir& work, const nlohmann::json& artifacts, const std::filesystem::path& to,
                           bool whole = false);

}  // namespace cgview::server
