// Jobs as child processes of the server, on its own machine: at most
// `max_workers` at once, each under an address-space limit
// (setrlimit(RLIMIT_AS) before exec) and a timer that kills it; progress
// from its stdout.  Cancelling sends SIGTERM, then SIGKILL a second later.
// Workers die with the server (shutdown kills them), so a job of an
// earlier run cannot be adopted.
#pragma once

#include <sys/types.h>

#include <map>
#include <mutex>
#include <set>

#include <memory>

#include "jobs/executor.h"
#include "sandbox.h"

namespace cgview::server {

class LocalExecutor : public Executor {
 public:
  // `worker`: the cgview-worker executable; `sandbox`: where each worker
  // starts (nullptr or off: a plain child process).
  LocalExecutor(std::filesystem::path worker, int max_workers, std::shared_ptr<const Sandbox> sandbox = nullptr);
  ~LocalExecutor() override;

  const char* name() const override { return "local"; }
  int capacity() const override { return max_workers_; }
  std::string launch(const LaunchSpec& job) override;
  bool adopt(const LaunchSpec&, const std::string&) override { return false; }
  void cancel(const std::string& job_id) override;
  std::vector<ExecutorEvent> poll(std::chrono::milliseconds timeout) override;
  void wake() override;
  void shutdown() override;
  bool sandboxed() const override { return sandbox_ && sandbox_->enabled(); }

 private:
  struct Run {
    pid_t pid = -1;
    Sandbox::Slot slot;  // the sandbox's user for it (a root server's)
    int out_fd = -1;     // the worker's stdout; -1 once it closed
    std::string out;
    std::string garbage;  // why it was stopped: its output was not progress lines
    std::chrono::steady_clock::time_point launched, term_sent;
    double timeout_s = 0;
    bool terminating = false, timed_out = false;
  };
  // Kills what is over its time or was cancelled a second ago; reaps what
  // exited (into `events`).
  void check(std::vector<ExecutorEvent>& events);

  std::filesystem::path worker_;
  int max_workers_;
  std::shared_ptr<const Sandbox> sandbox_;
  std::map<std::string, Run> runs_;     // by job id
  std::vector<ExecutorEvent> pending_;  // started events, sent at the next poll
  std::mutex cancel_mutex_;
  std::set<std::string> cancels_;  // asked from other threads, done in poll
  WakePipe wake_;
};

}  // namespace cgview::server
