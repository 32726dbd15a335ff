// A job as the server keeps it: what was asked (algorithm, inputs, checked
// parameters), where it stands (a state, its stage and progress), how it
// ended (error, artifacts) and where it runs (the executor and its handle:
// a process id, a Slurm job id).  The store (job_store.h) keeps every field
// but the run-time ones; job_json gives the shape clients read.
#pragma once

#include <chrono>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace cgview::server {

enum class JobState { queued, running, done, failed, cancelled, interrupted };

// "queued", "running", ... (the wire and stored names).
const char* to_string(JobState state);
// nullopt for a name that is none of them.
std::optional<JobState> job_state_from(const std::string& name);
// queued or running: the job has not ended.
inline bool active(JobState s) { return s == JobState::queued || s == JobState::running; }

struct Job {
  std::string id, owner, algorithm;
  std::string mesh_id, mesh_sha;                     // the first mesh input (a chained job's too)
  nlohmann::json inputs = nlohmann::json::object();  // every input by name: a mesh id or {"job", "artifact"}
  nlohmann::json params = nlohmann::json::object();  // canonical: checked, defaults filled in
  std::string cache_key;
  JobState state = JobState::queued;
  std::string stage, error, created, started, finished;
  double progress = 0;
  bool cached = false;
  nlohmann::json artifacts = nlohmann::json::array();  // the worker's list: name, kind, file, ...
  nlohmann::json warnings = nlohmann::json::array();   // the worker's (strings): what the user must be told
  std::string files;        // the job whose directory holds the artifacts (itself, or a cached one's)
  std::uint64_t bytes = 0;  // of its directory once ended (its owner's quota counts them)
  std::int64_t seq = 0;     // submission order
  // Where it runs: the executor's name and its handle for the job ("" while
  // queued); kept so that a restarted server finds a Slurm job again.
  std::string executor, handle;
  std::string where;  // the node it runs on, when the executor knows it
  // The SHA-256 of the token its worker uses to fetch inputs and send
  // results over the API (where the nodes do not share the data directory);
  // "" once it ended: the token dies with the job.
  std::string worker_token_sha;
  // Run-time only.
  bool cancelled = false;  // asked to stop: its state is already cancelled, its worker may still run
  bool in_flight = false;  // a worker may still write into its directory
  std::chrono::steady_clock::time_point last_event;
};

// The job as clients see it (GET /api/v1/jobs/ID): artifacts without their file names.
nlohmann::json job_json(const Job& job);
// A progress event: {"type": "job_progress", "job": {id, state, progress, stage}}.
nlohmann::json progress_event(const Job& job);

}  // namespace cgview::server
