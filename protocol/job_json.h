// A job as the server keeps and clients read it (protocol/API.md's `Job`):
// what was asked (algorithm, inputs, checked parameters), where it stands
// (a state, its stage and progress), how it ended (error, artifacts,
// warnings) and where it runs (the executor and its handle: a process id, a
// Slurm job id).  The server's store keeps every field; job_json gives the
// shape clients read.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace cgview::protocol {

enum class JobState { queued, running, done, failed, cancelled, interrupted };

// "queued", "running", ... (the wire and stored names).
const char* to_string(JobState state);
// nullopt for a name that is none of them.
std::optional<JobState> job_state_from(const std::string& name);
// queued or running: the job has not ended.
inline bool active(JobState s) { return s == JobState::queued || s == JobState::running; }

struct JobRecord {
  std::string id, owner, algorithm;
  std::string mesh_id, mesh_sha;                     // the first mesh input (a chained job's too)
  nlohmann::json inputs = nlohmann::json::object();  // every input by name: a mesh id or {"job", "artifact"}
  nlohmann::json params = nlohmann::json::object();  // canonical: checked, defaults filled in
  std::string cache_key;
  JobState state = JobState::queued;
  std::string stage, error, created, started, finished;
  // How long its run took, from its worker's start to its end, in seconds (0:
  // not known, as for a job that ran before a restart): the timestamps above
  // are whole seconds, and a grader sets time limits from a reference's run.
  double run_s = 0;
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
  // A plugin's algorithm (plugins): {"id", "name", "library": its file}; null otherwise.
  nlohmann::json plugin = nullptr;
};

// The job as clients see it (GET /api/v1/jobs/ID): artifacts without their
// file names, each with the formats its kind is served in.
nlohmann::json job_json(const JobRecord& job);
// A progress event: {"type": "job_progress", "job": {id, state, progress, stage}}.
nlohmann::json progress_event(const JobRecord& job);

}  // namespace cgview::protocol
