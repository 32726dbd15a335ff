// Where a job's worker runs.  The scheduler hands an executor one prepared
// job at a time (its directory holds job.json, the worker writes its
// results there) and hears back what happened: the worker started (and on
// which node), waits (and why), made progress, ended (and how).  Each
// implementation derives from ExecutorBase (below: the cancel requests, the
// wake pipe and the watchdog of the time limit, one copy for all) and is
// chosen by its name from executor_registry.h: local (a child process of the
// server: local_executor.h) and slurm (a batch job on the lab's cluster:
// slurm_executor.h).  What differs between them that the scheduler must
// know is in Executor::capabilities(), never in a test of the name.
//
// launch, adopt, poll and shutdown are called from the scheduler's thread
// only; cancel and wake from any thread.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
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
  // job.json's text.  It is also written in `dir` unless the executor takes
  // it from here alone (Capabilities::job_json_in_memory).
  std::string spec;
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
    not_started,    // where it was sent, its worker could not start (`detail` says why: a node without the data
                    // directory)
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
// job.json names them, the data directory hidden.  job.json is the file in
// the run's directory, or where `spec_fd` is given (a descriptor of the
// text, read from its start), that descriptor's bytes.  Throws IoError.
Sandbox::Command sandboxed_worker(const Sandbox& sandbox, const LaunchSpec& job, const std::filesystem::path& worker,
                                  int slot, ChildOptions options = {}, int spec_fd = -1);

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

class Executor {
 public:
  virtual ~Executor() = default;
  // Its name in the registry (executor_registry.h): stored with each job it runs.
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
  // What the scheduler does differently for it.
  struct Capabilities {
    // A run it lost (WorkerEnd::How::lost: the cluster forgot it) goes back to the queue.
    bool requeue_lost = false;
    // Its workers do not see the data directory: each fetches its inputs and
    // sends its results with its job's own token (scheduler.h's worker_*),
    // reaching the server at `server_url` ("": the server's own address).
    bool remote_data = false;
    std::string server_url;
    // The setting that makes its workers see the data directory, for the
    // message of what needs it (a plugin).
    std::string shared_data_setting;
    // Once it says a run ended, nothing of the run is left to write (a
    // sandbox's process namespace ends with its first process): the run's
    // artifacts are then moved out of its directory, not copied.
    bool run_ends_whole = false;
    // Its runs take job.json from LaunchSpec::spec, and no file of it is
    // written in the run's directory (one file fewer made and removed a run).
    bool job_json_in_memory = false;
  };
  virtual Capabilities capabilities() const { return {}; }
};

// What every executor shares: cancel requests taken from any thread and
// done in poll, the pipe that ends poll's wait, and the watchdog that holds
// each job to its time limit to the second (Slurm's own counts minutes).
class ExecutorBase : public Executor {
 public:
  void cancel(const std::string& job_id) final;
  void wake() final { wake_.wake(); }

 protected:
  // The jobs whose cancel was asked since the last call (the scheduler's thread).
  std::set<std::string> take_cancels();
  // poll's wait ends when this fd is readable (a cancel, a wake); drain it then.
  int wake_fd() const { return wake_.fd(); }
  void drain_wake() { wake_.drain(); }
  // The watchdog: the job's time limit counts from now (its worker started;
  // again when it starts again).  `timeout_s` 0: none.
  void watch(const std::string& job_id, double timeout_s);
  void unwatch(const std::string& job_id) { deadlines_.erase(job_id); }
  // The jobs over their time limit, each said once (no longer watched).
  std::set<std::string> overdue();

 private:
  std::mutex cancel_mutex_;
  std::set<std::string> cancels_;
  WakePipe wake_;
  std::map<std::string, std::chrono::steady_clock::time_point> deadlines_;
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
