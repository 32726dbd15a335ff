// The job scheduler: runs algorithms in worker processes (cgview-worker),
// one process per job, from a bounded pool, fair across owners (round-robin
// over the owners with queued jobs).  Each job has a time and a memory
// limit (setrlimit(RLIMIT_AS) in the child before exec, and a timer that
// kills); a crash or a limit fails that job alone.  Cancellation sends
// SIGTERM, then SIGKILL a second later.  Progress comes from the worker's
// stdout ("progress FRACTION STAGE").
//
// Jobs persist in the store's SQLite database (table jobs) and their
// artifacts under DATA/jobs/ID/; on start, jobs left queued or running by a
// previous run are queued again (or marked interrupted).  Results are
// cached by (mesh sha256, algorithm, canonical parameters): an identical
// job is answered done, cached, without running.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "mesh_service.h"
#include "quota.h"

struct sqlite3;

namespace cgview::server {

struct JobConfig {
  std::filesystem::path worker;  // the cgview-worker executable
  int max_workers = 0;           // 0: the number of cores
  double timeout_s = 3600;       // per job; 0: none
  std::size_t memory_mb = 8192;  // address-space limit per job; 0: none
  bool requeue_on_restart = true;  // else: jobs of a previous run are marked interrupted
  QuotaConfig quotas;  // per-user storage and concurrent-job limits
};

struct ArtifactBytes {
  std::string bytes, content_type, file_name;
};

// How many jobs there are, for the metrics.
struct JobCounts {
  std::map<std::pair<std::string, std::string>, std::size_t> by_state_algorithm;  // (state, algorithm) -> jobs
  std::size_t queued = 0, running = 0;
  std::uint64_t artifact_bytes = 0;  // of every job's directory
};

class JobScheduler {
 public:
  JobScheduler(MeshService& meshes, JobConfig config);
  ~JobScheduler();  // kills running workers; their jobs stay "running" in the store and run again at the next start
  JobScheduler(const JobScheduler&) = delete;
  JobScheduler& operator=(const JobScheduler&) = delete;

  // Starts running queued jobs (set on_event first).
  void start();
  // Called (from the scheduler's thread) with job_progress, job_done, job_failed
  // and job_cancelled events, and who may see them (the job's owner and shares).
  std::function<void(const nlohmann::json&, const Access&)> on_event;

  // GET /api/v1/algorithms: the algorithms a client may run (test ones hidden).
  nlohmann::json algorithms_json() const;
  // Throws std::out_of_range (unknown algorithm or mesh) or InvalidInput
  // (bad parameters, naming the parameter and the rule broken).
  // An input that names an earlier job's output mesh stores that mesh; its id
  // is appended to `new_meshes` when given (the router announces it).
  // The job belongs to the caller, whose every input must be readable: a
  // mesh or job of another user is unknown (std::out_of_range), as is one
  // that does not exist.
  nlohmann::json submit(const nlohmann::json& request, const Caller& caller = Caller::local(),
                        std::vector<std::string>* new_meshes = nullptr);
  // The jobs the caller may see (their own and those shared with them; an
  // admin's: all); get, cancel and artifact answer nullopt or
  // std::out_of_range for any other.
  nlohmann::json list(const Caller& caller = Caller::local()) const;
  std::optional<nlohmann::json> get(const std::string& id, const Caller& caller = Caller::local()) const;
  // Who reads a job the caller sees (its owner and shares); std::out_of_range
  // for any other.
  Access access(const std::string& id, const Caller& caller) const;
  // Cancels a queued or running job (its owner or an admin, else Forbidden);
  // the job (unchanged when it had ended).
  std::optional<nlohmann::json> cancel(const std::string& id, const Caller& caller = Caller::local());
  // An artifact of a done job in a format; throws std::out_of_range (no such
  // job or artifact), InvalidInput (job not done), UnsupportedFormat.
  ArtifactBytes artifact(const std::string& id, const std::string& name, const std::string& format,
                         const Caller& caller = Caller::local());

  std::uint64_t workers_started() const { return workers_started_; }
  JobCounts counts() const;

  // Quotas: a user's limits, and their use (the bytes of the meshes they own
  // and of their jobs' artifacts, cached results not counted twice; their
  // queued and running jobs).
  UserLimits limits(const Caller& caller) const { return config_.quotas.limits(caller); }
  Usage usage(const std::string& user) const;
  // Throws QuotaExceeded (413) when `adding` bytes ("this upload") would take
  // the caller over their storage quota.
  void check_storage(const Caller& caller, std::uint64_t adding, const std::string& what) const;

 private:
  struct Job;
  void load();
  void persist(const Job& job);
  // persist, or remember the job in unsaved_ when the write fails (never throws).
  void save(const Job& job);
  nlohmann::json job_json(const Job& job) const;
  void loop();
  bool launch(Job& job);  // under mutex_
  void reap(Job& job, int status, std::vector<nlohmann::json>& events);  // under mutex_
  void wake();
  std::filesystem::path job_dir(const std::string& id) const;
  // Whether the caller reads the job: theirs, shared with them, or admin.
  bool readable(const Job& job, const Caller& caller) const;
  // The job if the caller may see it (under mutex_); throws std::out_of_range.
  const Job& job_locked(const std::string& id, const Caller& caller) const;
  // Who may see a job's events.
  Access job_access(const std::string& id) const;
  // The file of a done job's artifact of that kind (under mutex_); throws
  // std::out_of_range (no such job or artifact) or InvalidInput (not done,
  // another kind).
  std::filesystem::path artifact_file_locked(const std::string& job, const std::string& name, const std::string& kind,
                                             const Caller& caller = Caller::local()) const;

  MeshService& meshes_;
  JobConfig config_;
  sqlite3* db_ = nullptr;
  std::map<std::string, nlohmann::json> worker_algorithms_;  // from cgview-worker --list
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::vector<std::string> order_;                            // ids, oldest first
  std::map<std::string, std::deque<std::string>> queues_;      // by owner
  std::string last_owner_;
  std::map<std::string, std::string> cache_;  // cache key -> the done job whose files hold the result
  bool stopping_ = false;
  std::int64_t seq_ = 0;
  // The jobs queued or running of the owner (under mutex_).
  int active_locked(const std::string& owner) const;
  std::atomic<std::uint64_t> workers_started_{0};
  // Jobs whose last change could not be written (a full disk): written again
  // at each turn of the loop until it fits; their state in memory is right.
  std::set<std::string> unsaved_;
  std::vector<std::string> running_ids_;
  int wake_pipe_[2] = {-1, -1};
  std::thread thread_;
};

}  // namespace cgview::server
