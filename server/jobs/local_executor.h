// Jobs as child processes of the server, on its own machine: at most
// `max_workers` at once, each under an address-space limit
// (setrlimit(RLIMIT_AS) before exec) and a timer that kills it; progress
// from its stdout.  Cancelling sends SIGTERM, then SIGKILL a second later.
// Workers die with the server (shutdown kills them), so a job of an
// earlier run cannot be adopted.
//
// Up to two workers are started ahead of the next jobs (pre-started: each
// in its own sandbox, its libraries loaded, waiting on its stdin), so that
// a job does not wait for bubblewrap, the worker's exec and its dynamic
// loading.  They are started when the executor has a free place and
// nothing to report: a burst's jobs, which fill every place, start their
// own, and a job's end is never said late for them.  Each takes one job
// only and is then that job's worker as one started for it would be: its own
// process, user, directory and limits.  Its inputs and plugin are linked
// into directories its sandbox was given, its job.json is written into
// the file it was given, its job directory is renamed to the run's and
// it goes.  A job that finds none ready (a burst), or that one does not
// fit (another memory limit, an input that cannot be linked
// there) starts a worker of its own instead.
#pragma once

#include <sys/types.h>

#include <deque>
#include <map>
#include <optional>

#include <memory>

#include "jobs/executor.h"
#include "sandbox.h"

namespace cgview::server {

class LocalExecutor : public ExecutorBase {
 public:
  // `worker`: the cgview-worker executable; `sandbox`: where each worker
  // starts (nullptr or off: a plain child process).
  LocalExecutor(std::filesystem::path worker, int max_workers, std::shared_ptr<const Sandbox> sandbox = nullptr);
  ~LocalExecutor() override;

  static constexpr const char* kName = "local";  // in the registry (executor_registry.cpp)
  const char* name() const override { return kName; }
  int capacity() const override { return max_workers_; }
  std::string launch(const LaunchSpec& job) override;
  bool adopt(const LaunchSpec&, const std::string&) override { return false; }
  std::vector<ExecutorEvent> poll(std::chrono::milliseconds timeout) override;
  void shutdown() override;
  bool sandboxed() const override { return sandbox_ && sandbox_->enabled(); }
  Capabilities capabilities() const override {
    Capabilities c;
    c.run_ends_whole = sandboxed();
    c.job_json_in_memory = sandboxed();
    return c;
  }

 private:
  struct Run {
    pid_t pid = -1;
    Sandbox::Slot slot;  // the sandbox's user for it (a root server's)
    int out_fd = -1;     // the worker's stdout; -1 once it closed
    std::string out;
    // A worker started for its job in the sandbox: its stderr, a pipe (-1
    // once it closed), the first kMaxReportBytes of it kept (the rest read
    // and dropped), written to `dir`/stderr.txt at its end where there was
    // any: no file made for the many runs that print nothing.
    int err_fd = -1;
    std::string err;
    std::filesystem::path dir;
    std::string garbage;  // why it was stopped: its output was not progress lines
    std::chrono::steady_clock::time_point term_sent;
    bool terminating = false, timed_out = false;
    std::filesystem::path warm_dir;  // a pre-started worker's own directory, removed when it is reaped
    // A pre-started worker not yet ready: its stdin, closed (go) once it
    // said it is ready and its directory was renamed to `work`, the run's.
    int go_fd = -1;
    std::filesystem::path work;
  };
  // A worker started, sandboxed where there is a sandbox, for `job`'s
  // directories, with `stdin_fd` as its stdin (-1: none).  Its job.json is
  // the file in `job.dir` and its stderr `job.dir`/stderr.txt, or where
  // `in_memory` (a sandboxed worker started for its job), job.spec copied
  // into its sandbox and a pipe (err_fd): two files fewer made and removed
  // a job (on ext4 without a journal, each new file is a scan past the
  // inodes freed in the last minutes).  Throws LaunchError.
  struct Started {
    pid_t pid = -1;
    Sandbox::Slot slot;
    int out_fd = -1, err_fd = -1;
  };
  Started start_worker(const LaunchSpec& job, int stdin_fd, bool in_memory = false);
  // Reads what the run's stderr pipe holds now, up to its end (then closed).
  static void read_stderr(Run& r);
  // A pre-started worker: its directory (runs/warm-N) holds the job.json
  // it was given, its stderr.txt, work/ (the job's directory once renamed),
  // in/ and plugin/ (seen read-only where a job's inputs and plugin are).
  struct Warm {
    Started worker;
    std::string out;  // what it wrote so far (kWorkerReady, once it is ready)
    int go_fd = -1;   // its stdin, closed once its job can go
    std::filesystem::path dir;
    std::size_t memory_mb = 0;
  };
  // How many workers wait ahead: two, so that a job that comes as the one
  // before it ends finds one started a job earlier, ready by then.
  static constexpr std::size_t kWorkersAhead = 2;
  bool start_warm(const LaunchSpec& like);  // false: none started (the next job starts its own)
  bool ready(Warm& w);                      // it wrote kWorkerReady
  // The job's inputs, plugin, job.json and stderr to `w`; false: it does
  // not fit, `w` stays as it was.
  bool hand_over(Warm& w, const LaunchSpec& job);
  void go_when_ready(Run& r);  // go, once r.out holds kWorkerReady
  bool go(Run& r);
  void drop_warm(Warm& w);
  // Kills what is over its time or was cancelled a second ago; reaps what
  // exited (into `events`).
  void check(std::vector<ExecutorEvent>& events);

  std::filesystem::path worker_;
  int max_workers_;
  std::shared_ptr<const Sandbox> sandbox_;
  std::map<std::string, Run> runs_;                    // by job id
  std::vector<ExecutorEvent> pending_;                 // started events, sent at the next poll
  std::deque<Warm> warm_;                              // the workers ahead, oldest first
  std::optional<LaunchSpec> warm_like_;                // the last job launched: workers ahead are started for its like
  std::vector<std::filesystem::path> used_warm_dirs_;  // of reaped pre-started workers, to remove
  int warms_ = 0;                                      // started so far: each its own directory
};

}  // namespace cgview::server
