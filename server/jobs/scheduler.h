// The job scheduler: takes job requests (admission.h), keeps the jobs
// (job.h, in job_store.h's table), queues them fairly across owners
// (fair_queue.h) and hands them to an executor (executor.h: this machine's
// processes, or a Slurm cluster), one worker per job.  A crash or a limit
// fails that job alone; cancelling stops its worker.  Results are cached by
// (input contents, algorithm, canonical parameters): an identical job is
// answered done, cached, without running.
//
// Jobs persist: after a restart, a job the executor still runs (a Slurm
// job, by its stored id) is followed again; any other left queued or
// running is queued again (or marked interrupted, by setting).
#pragma once

#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "jobs/admission.h"
#include "artifacts/artifact_codec.h"
#include "jobs/executor.h"
#include "jobs/fair_queue.h"
#include "jobs/job.h"
#include "jobs/job_store.h"
#include "jobs/slurm_config.h"
#include "jobs/worker_result.h"
#include "mesh_service.h"
#include "quota.h"

namespace cgview::server {

class Sandbox;

struct JobConfig {
  std::filesystem::path worker;      // the cgview-worker executable
  int max_workers = 0;               // local: jobs at once (0: the number of cores)
  double timeout_s = 3600;           // per job; 0: none
  std::size_t memory_mb = 8192;      // address-space limit per job; 0: none
  std::uint64_t max_files = 100000;  // names (files, directories, links) in a running job's directory
  int cpus = 1;                      // per job (Slurm's --cpus-per-task)
  bool requeue_on_restart = true;    // else: jobs of a previous run that cannot be followed are marked interrupted
  QuotaConfig quotas;                // per-user storage and concurrent-job limits
  std::string executor = "local";    // a name in executor_registry.h
  SlurmConfig slurm;                 // the slurm executor's settings
  // Where local workers start (sandbox.h); nullptr: plain child processes.
  std::shared_ptr<const Sandbox> sandbox;
};

// A worker's request with a token that is not its job's (or the job ended): 401.
struct WorkerTokenRefused : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// How many jobs there are, for the metrics.
struct JobCounts {
  std::map<std::pair<std::string, std::string>, std::size_t> by_state_algorithm;  // (state, algorithm) -> jobs
  std::size_t queued = 0, running = 0;
  std::uint64_t artifact_bytes = 0;  // of every job's directory
};

class JobScheduler : private JobLookup {
 public:
  // Throws InvalidInput for an executor it does not know, or as its factory
  // does (executor_registry.h: a Slurm cluster that no job fits).
  JobScheduler(MeshService& meshes, JobConfig config);
  ~JobScheduler();  // local workers are killed (their jobs run again at the next start); Slurm's go on
  JobScheduler(const JobScheduler&) = delete;
  JobScheduler& operator=(const JobScheduler&) = delete;

  // Starts running queued jobs (set on_event first, and the server's URL).
  void start();
  // How a worker on another machine reaches this server (used where the
  // nodes do not share the data directory and the config names no server_url).
  void set_server_url(const std::string& url) { server_url_ = url; }
  // Called (from the scheduler's thread) with job_progress, job_done, job_failed
  // and job_cancelled events, and who may see them (the job's owner and shares).
  std::function<void(const nlohmann::json&, const Access&)> on_event;

  // GET /api/v1/algorithms: the algorithms a client may run (test ones hidden).
  nlohmann::json algorithms_json() const { return admission_.algorithms_json(); }
  // How a request's "plugin" is found (plugin_service.h); set before start.
  void set_plugin_resolver(PluginResolver r) { admission_.set_plugin_resolver(std::move(r)); }
  // Admits and queues a job (admission.h says what it checks); the job.
  // Throws as Admission::admit does, or QuotaExceeded.
  // Data another tool made, stored as the artifact of a done job of the
  // caller's (algorithm "import", its file's name as its parameter, `inputs`
  // the mesh a field is for): it shows, slices, compares and feeds jobs as a
  // result does.  `read` stores the artifact into the directory it is given
  // and returns its entry and warnings (data_read.h); what it throws is
  // thrown, with nothing kept.  Also throws QuotaExceeded, InvalidInput for
  // an artifact whose files do not match its entry.
  using DataReader = std::function<std::pair<nlohmann::json, std::vector<std::string>>(const std::filesystem::path&)>;
  nlohmann::json import_data(const std::string& file_name, const nlohmann::json& inputs, const DataReader& read,
                             const Caller& caller);
  // `system`: the server's own job (a plugin build, a graded run), which may
  // run a hidden system algorithm and set "timeout_s", a shorter time limit.
  nlohmann::json submit(const nlohmann::json& request, const Caller& caller = Caller::local(),
                        std::vector<std::string>* new_meshes = nullptr, bool system = false);
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
  // DELETE of a job (its owner or an admin, else Forbidden): an ended job
  // is deleted with its results (results that other jobs answer from,
  // identical cached ones, stay until the last of them goes); one still
  // queued or running, or not yet back from its executor, is cancelled
  // instead, and `cancelled` is the job as cancel() answers it.
  struct Removal {
    bool found = false;  // false: the caller sees no such job
    std::optional<nlohmann::json> cancelled;
  };
  Removal remove(const std::string& id, const Caller& caller = Caller::local());
  // An artifact of a done job in a format; throws std::out_of_range (no such
  // job or artifact), InvalidInput (job not done), UnsupportedFormat.
  ExportedArtifact artifact(const std::string& id, const std::string& name, const std::string& format,
                            const Caller& caller = Caller::local()) override;
  // A done job's artifact read back by its kind's codec, if it is of `kind`:
  // throws as artifact() does (UnsupportedFormat for another kind).
  ArtifactValue artifact_value(const std::string& id, const std::string& name, OutputKind kind,
                               const Caller& caller = Caller::local()) const;

  // The worker's side of a job whose node does not see the data directory
  // (the Slurm executor's shared_data false).  Each call takes the job's
  // own token, valid while the job runs and for nothing else; any other
  // token, or a job that ended, is WorkerTokenRefused.
  // Its job.json (input files and the output directory, relative to the worker's).
  std::string worker_spec(const std::string& id, std::string_view token) const;
  // The file of its input `name`.
  std::filesystem::path worker_input(const std::string& id, std::string_view token, const std::string& name) const;
  // Writes one of its results (`file`: a plain name, not job.json) into the
  // job's directory; throws InvalidInput for a bad name, DiskFull.
  void worker_put(const std::string& id, std::string_view token, const std::string& file, const std::string& bytes);
  // Its progress line ("progress F STAGE"), as its stdout would carry it.
  void worker_progress(const std::string& id, std::string_view token, const std::string& line);

  std::uint64_t workers_started() const { return workers_started_; }
  JobCounts counts() const;

  // Quotas: a user's limits, and their use (the bytes of the meshes they own
  // and of their jobs' artifacts, cached results not counted twice; their
  // queued and running jobs).
  UserLimits limits(const Caller& caller) const { return config_.quotas.limits(caller); }
  Usage usage(const std::string& user) const;
  // Throws QuotaExceeded (413) when `adding` bytes ("this upload") would take
  // the caller over their storage quota.
  void check_storage(const Caller& caller, std::uint64_t adding, const std::string& what) const override;

 private:
  // JobLookup, for admission.
  std::filesystem::path artifact_file(const std::string& job, const std::string& artifact, const std::string& kind,
                                      const Caller& caller) const override;
  void check_job_count(const Caller& caller) const override;

  void load();
  // Writes the job, or remembers it in unsaved_ when the write fails (never throws).
  void save(const Job& job);
  void loop();
  // Writes the job's job.json (its input files resolved); the spec to launch
  // it, or nullopt with job.error set (under mutex_).
  std::optional<LaunchSpec> prepare(Job& job);
  LaunchSpec spec(const Job& job) const;
  // The job's time limit: its own where the server set a shorter one, else the server's.
  double effective_timeout(const Job& job) const;
  // The limits its workers run under, for the messages of their failures.
  WorkerLimits limits_of_workers() const;
  // Every input of the job by name -> its file on this machine; "" with
  // *error set when one is gone (under mutex_).
  std::optional<nlohmann::json> input_files(const Job& job, std::string* error) const;
  bool remote_data() const { return executor_->capabilities().remote_data; }
  // The in-flight job whose token this is (under mutex_); throws WorkerTokenRefused.
  const Job& worker_job_locked(const std::string& id, std::string_view token) const;
  // What an ended run left, read outside mutex_ (the run's files are the
  // job's, hostile input: job_files.h): its outcome, with its artifacts
  // already taken into the job's results directory when it is done.
  // Each ended run's directory is removed once read.
  struct Collected {
    WorkerOutcome outcome;
    bool stopped = false;     // the server stopped it (check_disk): it fails, never queued again
    std::uint64_t bytes = 0;  // what the job keeps (its results directory)
  };
  std::map<std::string, Collected> collect(const std::vector<ExecutorEvent>& happened);
  Collected collect_run(const ExecutorEvent& ended, const std::string& owner);
  // Applies what the executor said (under mutex_); events to send.
  void apply(const ExecutorEvent& e, std::vector<nlohmann::json>& events, const Collected* collected);
  // The job ended (its worker gone, or its launch failed) (under mutex_);
  // `collected` is what collect() read of its run (nullptr: nothing to read).
  void end(Job& job, const WorkerEnd* how, std::vector<nlohmann::json>& events, const Collected* collected = nullptr);
  // Whether an ended run of the job goes back to the queue (Slurm lost it) (under mutex_).
  bool requeued_when_lost(const WorkerEnd& how) const;
  // A job's results, served from here: only the server writes there.
  std::filesystem::path job_dir(const std::string& id) const;
  // A run of a job: the server's files of the run, and work/, the job's own
  // (executor.h's LaunchSpec); made fresh for each run, removed at its end.
  std::filesystem::path run_dir(const std::string& id) const;
  // Whether the caller reads the job: theirs, shared with them, or admin.
  bool readable(const Job& job, const Caller& caller) const;
  // The job if the caller may see it (under mutex_); throws std::out_of_range.
  const Job& job_locked(const std::string& id, const Caller& caller) const;
  // Who may see a job's events.
  Access job_access(const std::string& id) const;
  // artifact_file, under mutex_.
  // A done job's artifact the caller may read: its job's directory and its
  // entry in the worker's list; throws as artifact() does.
  std::pair<std::filesystem::path, nlohmann::json> stored_artifact(const std::string& id, const std::string& name,
                                                                   const Caller& caller) const;
  std::filesystem::path artifact_file_locked(const std::string& job, const std::string& name, const std::string& kind,
                                             const Caller& caller = Caller::local()) const;
  // Forgets an ended job (under mutex_): the results directory to remove
  // with it, "" when another job (a cached twin) still answers from it.
  std::string forget_locked(std::string id);  // by value: a caller may pass the id of the Job it erases
  // The jobs the owner has queued or running (under mutex_).
  int active_locked(const std::string& owner) const;

  MeshService& meshes_;
  JobConfig config_;
  Admission admission_;
  JobStore store_;
  std::unique_ptr<Executor> executor_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<Job>> jobs_;
  std::vector<std::string> order_;  // ids, oldest first
  FairQueue queue_;
  std::set<std::string> in_flight_;           // handed to the executor and not ended
  std::map<std::string, std::string> cache_;  // cache key -> the done job whose files hold the result
  bool stopping_ = false;
  std::int64_t seq_ = 0;
  std::atomic<std::uint64_t> workers_started_{0};
  // Runs that never started (their preparation or launch failed), whose
  // directories go outside mutex_; a run that ended goes in collect().
  std::vector<std::filesystem::path> leftovers_;  // run and results directories to remove outside the lock
  // A running job's directory, walked every few seconds outside mutex_:
  // one over its owner's room (their storage quota) or over max_files
  // names is stopped, and fails with why (by job id, under mutex_).
  void check_disk();
  std::map<std::string, std::string> over_disk_;
  std::chrono::steady_clock::time_point last_disk_check_{};
  // The room its owner has left under their storage quota (the most a job's files may take).
  std::uint64_t room_of(const std::string& owner) const;
  // Jobs whose last change could not be written (a full disk): written again
  // at each turn of the loop until it fits; their state in memory is right.
  std::set<std::string> unsaved_;
  std::string server_url_;
  std::thread thread_;
};

}  // namespace cgview::server
