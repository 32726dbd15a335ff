// Jobs as batch jobs on a Slurm cluster: one `sbatch` per CGView job
// (named cgview-ID, with the job's time, memory and CPU count), one
// `squeue` per poll cycle for every job in flight, `scancel` to stop.
// Slurm's own command-line tools, not libslurm: they keep their interface
// across Slurm releases where libslurm's ABI changes with each (and the
// server then needs no Slurm headers to build).
//
// The batch script runs cgview-worker on the job's directory (on the data
// directory the nodes share) under the job's address-space limit, and
// writes the worker's exit status beside its results (worker.exit): how
// the worker really ended is known from that file even where Slurm reports
// a launch failure, or has forgotten the job.  Progress comes from the
// worker's output file (Slurm's --output).
#pragma once

#include <chrono>
#include <map>
#include <optional>

#include "jobs/executor.h"
#include "jobs/slurm_config.h"

namespace cgview::server {

class SlurmExecutor : public ExecutorBase {
 public:
  // Throws InvalidInput when Slurm's tools are not on PATH, or when no node
  // of the cluster (of slurm.partition) has the `memory_mb` a job asks (the
  // server's job_memory_mb; 0: none): every job would be refused.
  // A sandbox that is on wraps each worker (with a shared data directory
  // and slurm.sandbox): the nodes run the same bubblewrap command.
  SlurmExecutor(SlurmConfig config, std::filesystem::path worker, std::shared_ptr<const Sandbox> sandbox = {},
                std::size_t memory_mb = 0);

  static constexpr const char* kName = "slurm";  // in the registry (executor_registry.cpp)
  const char* name() const override { return kName; }
  // Its running jobs and max_pending more, at most max_jobs.
  int capacity() const override;
  std::string launch(const LaunchSpec& job) override;
  bool adopt(const LaunchSpec& job, const std::string& handle) override;
  std::vector<ExecutorEvent> poll(std::chrono::milliseconds timeout) override;
  void shutdown() override {}  // the cluster's jobs outlive the server
  bool sandboxed() const override;
  Capabilities capabilities() const override;

  // The sbatch command line for a job, and its batch script.
  std::vector<std::string> sbatch_command(const LaunchSpec& job) const;
  std::string batch_script(const LaunchSpec& job, int slot = 0) const;
  // How many squeue calls it made (one per poll cycle).
  std::uint64_t squeue_calls() const { return squeue_calls_; }

 private:
  struct Tracked {
    LaunchSpec spec;
    Sandbox::Slot slot;  // its sandbox's user (a root server's), while it is in the cluster
    std::string slurm_id;
    bool running = false;            // a started event was sent
    bool cancelling = false;         // scancel sent
    bool timed_out = false;          // our watchdog cancelled it over its time limit
    std::string reason;              // the pending reason last reported
    std::string node;                // where squeue last said it is (or was)
    std::string output_file;         // the run's output file being read (the newest run's: stdout.N)
    std::uintmax_t output_read = 0;  // bytes of it read for progress
    std::string output;              // a partial line
    std::string garbage;             // why it was cancelled: its output was not progress lines
    int unseen = 0;                  // polls in a row that squeue did not list it
    // Since when the cluster holds it (pending) while its newest run has ended.
    std::optional<std::chrono::steady_clock::time_point> held_since;
  };
  // One squeue for every job; events for what changed.
  void refresh(std::vector<ExecutorEvent>& events);
  // How a job that left the cluster ended (Slurm's final state, or none).
  WorkerEnd ended(const Tracked& t, const std::string& state, const std::string& reason) const;
  void read_progress(Tracked& t, std::vector<ExecutorEvent>& events);
  // Whether the cluster has held the job (pending) for long with its newest
  // run ended and its result on disk.
  bool held_with_a_result(Tracked& t, std::chrono::steady_clock::time_point now) const;
  // Why no node takes a job of `memory_mb` ("": one does, or Slurm did not
  // answer); `answered` says whether it did.
  std::string memory_problem(std::size_t memory_mb, bool* answered) const;
  // Why a job that ended as `state` left nothing in its run's directory
  // where its node should have written ("": it did, or it never ran).
  std::string unseen_data(const Tracked& t, const std::string& state, const std::string& said) const;

  SlurmConfig config_;
  std::shared_ptr<const Sandbox> sandbox_;
  std::filesystem::path worker_;
  std::filesystem::path sbatch_, squeue_, scancel_, scontrol_;
  std::filesystem::path sinfo_;
  std::map<std::string, Tracked> jobs_;  // by CGView job id
  std::chrono::steady_clock::time_point last_refresh_{};
  std::uint64_t squeue_calls_ = 0;
  // The job memory checked against the nodes' (0: not yet: Slurm did not
  // answer at the start, it is asked again at the next launch).
  std::size_t memory_checked_ = 0;
};

}  // namespace cgview::server
