// Where a job's worker runs.  The scheduler hands an executor one prepared
// job at a time (its directory holds job.json, the worker writes its
// results there) and hears back what happened: the worker started (and on
// which node), waits (and why), made progress, ended (and how).  Two
// implementations: local (a child process of the server: local_executor.h)
// and slurm (a batch job on the lab's cluster: slurm_executor.h).
//
// launch, adopt, poll and shutdown are called from the scheduler's thread
// only; cancel and wake from any thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "sandbox.h"

namespace cgview::server {

struct LaunchSpec {
  std::string job_id;
  std::string name;  // what the job is called where it runs ("cgview-ID")
  // The run's directory, the server's side of one run: job.json, the batch
  // script, the worker's stdout and stderr and its exit status.  The job
  // never sees it (a plugin cannot plant a link there for the server, or
  // for a batch script, to follow).
  std::filesystem::path dir;
  // The job's own directory inside it (dir/work), the one place the job
  // writes: its results, error.txt, its /tmp.  Made fresh for every run.
  std::filesystem::path work;
  double timeout_s = 0;       // 0: none
  std::size_t memory_mb = 0;  // 0: none
  int cpus = 1;
  // Where the worker cannot see the data directory: the server's address,
  // the job's own token for its inputs and results (worker_api in
  // scheduler.h), and its inputs by name with the file each becomes beside
  // the worker (job.json, fetched too, names those files).  Empty otherwise.
  std::string server_url, token;
  std::map<std::string, std::string> remote_inputs;
  // What a sandboxed worker (sandbox.h) sees besides the system and its
  // directory: its input files and plugin library, read-only; the data
  // directory they live in is otherwise hidden.
  std::vector<std::pair<std::filesystem::path, std::string>> read_only;  // file -> where the job sees it
  std::filesystem::path data_dir;
};

// How a worker ended, as its executor saw it; the scheduler reads the
// worker's own report (result.json, error.txt) in its work directory.
struct WorkerEnd {
  enum class How {
    exited,         // with `code`
    signaled,       // by `signal`
    timed_out,      // its time limit
    out_of_memory,  // its memory limit (where the executor knows it: Slurm)
    node_failed,    // the machine it ran on went away
    lost,           // its executor no longer knows it (`detail` says why)
    garbled,        // it wrote something other than progress lines on its progress pipe (`detail` quotes it)
  };
  How how = How::exited;
  int code = 0, signal = 0;
  std::string detail;  // the executor's own words (a Slurm state and reason), for the message
};

struct ExecutorEvent {
  enum class Kind {
    started,   // the worker runs now, on `node` ("" where there is one machine)
    waiting,   // launched but not yet running: `reason` says why (Slurm's pending reason)
    progress,  // `progress` (0..1) and `stage`, from the worker's "progress F STAGE" lines
    ended,     // `end`
  };
  std::string job_id;
  Kind kind = Kind::progress;
  double progress = 0;
  std::string stage, node, reason;
  WorkerEnd end;
};

// A launch that failed: what() says why (the job fails with it).
struct LaunchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The command that runs `worker` on the job in `sandbox`: its directory the
// only writable one, its inputs, plugin and the worker read-only where
// job.json names them, the data directory hidden.  Throws IoError.
Sandbox::Command sandboxed_worker(const Sandbox& sandbox, const LaunchSpec& job, const std::filesystem::path& worker,
                                  int slot, ChildOptions options = {});

class Executor {
 public:
  virtual ~Executor() = default;
  // "local" or "slurm": stored with each job it runs.
  virtual const char* name() const = 0;
  // How many jobs it takes at once (launched and not ended).
  virtual int capacity() const = 0;
  // Starts the job's worker and returns its handle (a pid, a Slurm job id).
  // A started event follows (at once where there is no queue); throws
  // LaunchError.
  virtual std::string launch(const LaunchSpec& job) = 0;
  // Follows again a job that an earlier run of the server launched, by its
  // stored handle; false when this executor cannot (its worker died with
  // that server).
  virtual bool adopt(const LaunchSpec& job, const std::string& handle) = 0;
  // Asks the job's worker to stop; its end comes as an ended event.
  virtual void cancel(const std::string& job_id) = 0;
  // Waits until something happens or `timeout` passes (or wake), and says what happened.
  virtual std::vector<ExecutorEvent> poll(std::chrono::milliseconds timeout) = 0;
  virtual void wake() = 0;
  // The server stops: workers that cannot outlive it are killed (their jobs
  // run again at the next start); the cluster's go on.
  virtual void shutdown() = 0;
  // Whether its workers start in the sandbox (they then see the paths of sandbox.h).
  virtual bool sandboxed() const { return false; }
};

// A pipe that ends an executor's wait from another thread (cancel, a new
// job): poll its fd(), then drain() it.
class WakePipe {
 public:
  WakePipe();  // throws IoError
  ~WakePipe();
  WakePipe(const WakePipe&) = delete;
  WakePipe& operator=(const WakePipe&) = delete;
  void wake();
  void drain();
  int fd() const { return fds_[0]; }

 private:
  int fds_[2] = {-1, -1};
};

// What a worker's output held.  `garbage` is not empty when the output is
// not progress lines: a line of anything else, a fraction that is not a
// number, a line longer than kMaxProgressLine.  Its executor then stops the
// worker and the job fails with `garbage` as its message: a worker whose
// own pipe is garbled is broken, and its results are not trusted.
struct ProgressRead {
  bool found = false;   // a progress line came: `progress` and `stage` are the last one's
  std::string garbage;  // why the output is not progress lines (quoting it), or empty
};
inline constexpr std::size_t kMaxProgressLine = 4096;
// The line a pre-started worker (local_executor.h) writes when it waits for
// its job: its sandbox is set up and its libraries are loaded.  A progress
// line, so that it is never taken for garbage.
inline constexpr std::string_view kWorkerReady = "progress 0 ready\n";

// Parses the worker's progress lines out of `buffer` (its output so far,
// consumed up to the last newline).
ProgressRead read_progress_lines(std::string& buffer, double& progress, std::string& stage);

}  // namespace cgview::server
