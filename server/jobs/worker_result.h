// What a job's worker left behind, read once it ended: done with its
// artifacts (each file there and whole), or failed with a message a person
// understands, from the worker's own report (error.txt, stderr.txt) and
// how its executor saw it end.
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "jobs/executor.h"
#include "jobs/artifact_files.h"
#include "jobs/job_files.h"

namespace cgview::server {

struct WorkerOutcome {
  bool done = false;
  nlohmann::json artifacts = nlohmann::json::array();  // when done
  nlohmann::json warnings = nlohmann::json::array();   // when done: the worker's, strings
  std::string error;                                   // when not
};

// The limits the job ran under, for the messages.
struct WorkerLimits {
  double timeout_s = 0;
  std::size_t memory_mb = 0;
  // Where it ran in the sandbox (sandbox.h): its process and file-size
  // limits, so that a failure the sandbox caused says so.
  bool sandboxed = false;
  int processes = 0;
  std::size_t file_mb = 0;
  // The most its artifacts may take together (the owner's room left under
  // their storage quota, where they have one).
  std::uint64_t result_bytes = ~std::uint64_t(0);
};

// What the worker left: its report and results in `work` (the directory
// the job wrote), what its executor kept of its stderr in `run` (a
// directory the job never sees).  Both are read as hostile (job_files.h):
// a link, a FIFO or a file over its cap fails the job with a message.
WorkerOutcome read_worker_outcome(const JobDir& work, const JobDir& run, const WorkerEnd& end,
                                  const WorkerLimits& limits);

}  // namespace cgview::server
