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
};

WorkerOutcome read_worker_outcome(const std::filesystem::path& dir, const WorkerEnd& end, const WorkerLimits& limits);

// Why a worker's artifact list does not match its files ("" when it does):
// each entry names a plain file of the job's directory that is there, a
// scalar field's file holds its count of floats, only text may be empty, and
// each file has the size its worker wrote it with ("bytes").
std::string incomplete_artifact(const std::filesystem::path& dir, const nlohmann::json& artifacts);

}  // namespace cgview::server
