#include "jobs/local_executor.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <thread>

#include "child_process.h"
#include "core/errors.h"

namespace cgview::server {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

namespace {

// Whether the child has exited, leaving it unreaped.
bool exited(pid_t pid) {
  siginfo_t info{};
  return ::waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid;
}

}  // namespace

LocalExecutor::LocalExecutor(fs::path worker, int max_workers, std::shared_ptr<const Sandbox> sandbox)
    : worker_(std::move(worker)),
      max_workers_(max_workers > 0 ? max_workers : int(std::max(1u, std::thread::hardware_concurrency()))),
      sandbox_(std::move(sandbox)) {}

LocalExecutor::~LocalExecutor() { shutdown(); }

std::string LocalExecutor::launch(const LaunchSpec& job) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw LaunchError("pipe failed");
  ChildOptions child;
  child.memory_mb = job.memory_mb;
  child.stdout_fd = fds[1];
  child.stderr_file = job.dir / "stderr.txt";  // in the run's directory, out of the job's reach
  child.clean_env = true;
  child.end_with_server = true;
  const std::vector<std::string> argv = {worker_.string(), (job.dir / "job.json").string()};
  pid_t pid = -1;
  Sandbox::Slot slot;
  if (sandbox_ && sandbox_->enabled()) {
    slot = sandbox_->take_slot();
    Sandbox::Command c;
    try {
      c = sandboxed_worker(*sandbox_, job, worker_, slot.number(), child);
    } catch (const std::exception& e) {
      ::close(fds[0]);
      ::close(fds[1]);
      throw LaunchError(e.what());
    }
    pid = spawn_child(c.argv, c.options);
  } else {
    pid = spawn_child(argv, child);
  }
  ::close(fds[1]);
  if (pid < 0) {
    ::close(fds[0]);
    throw LaunchError("fork failed");
  }
  ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
  Run& r = runs_[job.job_id];
  r.pid = pid;
  r.slot = std::move(slot);
  r.out_fd = fds[0];
  r.launched = Clock::now();
  r.timeout_s = job.timeout_s;
  ExecutorEvent e;
  e.job_id = job.job_id;
  e.kind = ExecutorEvent::Kind::started;
  pending_.push_back(e);
  return std::to_string(pid);
}

void LocalExecutor::cancel(const std::string& job_id) {
  {
    std::lock_guard lock(cancel_mutex_);
    cancels_.insert(job_id);
  }
  wake();
}

void LocalExecutor::wake() { wake_.wake(); }

void LocalExecutor::check(std::vector<ExecutorEvent>& events) {
  std::set<std::string> cancels;
  {
    std::lock_guard lock(cancel_mutex_);
    cancels.swap(cancels_);
  }
  const auto now = Clock::now();
  for (auto it = runs_.begin(); it != runs_.end();) {
    Run& r = it->second;
    if (cancels.count(it->first) && !r.terminating) {
      r.terminating = true;
      r.term_sent = now;
      // A sandboxed worker never sees a SIGTERM: bubblewrap does not pass it
      // on, and the sandbox's first process, the init of its own process
      // namespace, ignores it.  That process, still in bubblewrap's group
      // while it sets the sandbox up, outlived a bubblewrap ended by SIGTERM
      // when the server died before the SIGKILL a second later.  So the
      // whole group is killed at once.
      kill_child(r.pid, sandboxed() ? SIGKILL : SIGTERM);
    }
    if (!r.terminating && !r.timed_out && r.timeout_s > 0 &&
        now - r.launched > std::chrono::duration<double>(r.timeout_s)) {
      r.timed_out = true;
      kill_child(r.pid, SIGKILL);
    }
    if (r.terminating && now - r.term_sent > std::chrono::seconds(1)) kill_child(r.pid, SIGKILL);
    int status = 0;
    // Reaped once its stdout closed (it exited, or closed it and goes on),
    // and what it left in its process group is killed first: nothing of a
    // job outlives it.  (Before the reaping, so that the group's number is
    // still the job's.)
    if (r.out_fd < 0 && exited(r.pid)) {
      kill_child(r.pid, SIGKILL);
      ::waitpid(r.pid, &status, 0);
      ExecutorEvent e;
      e.job_id = it->first;
      e.kind = ExecutorEvent::Kind::ended;
      if (!r.garbage.empty()) e.end.how = WorkerEnd::How::garbled, e.end.detail = r.garbage;
      else if (r.timed_out) e.end.how = WorkerEnd::How::timed_out;
      else if (WIFSIGNALED(status)) e.end.how = WorkerEnd::How::signaled, e.end.signal = WTERMSIG(status);
      // bubblewrap exits with 128 + the signal that ended the worker inside.
      else if (sandboxed() && WEXITSTATUS(status) > 128)
        e.end.how = WorkerEnd::How::signaled, e.end.signal = WEXITSTATUS(status) - 128;
      else e.end.how = WorkerEnd::How::exited, e.end.code = WEXITSTATUS(status);
      events.push_back(std::move(e));
      it = runs_.erase(it);
      continue;
    }
    ++it;
  }
}

std::vector<ExecutorEvent> LocalExecutor::poll(std::chrono::milliseconds timeout) {
  std::vector<ExecutorEvent> events = std::move(pending_);
  pending_.clear();
  check(events);
  if (!events.empty()) timeout = std::chrono::milliseconds(0);
  std::vector<pollfd> fds;
  std::vector<std::string> ids;
  bool exited_unreaped = false;
  for (const auto& [id, r] : runs_) {
    if (r.out_fd >= 0) {
      fds.push_back({r.out_fd, POLLIN, 0});
      ids.push_back(id);
    } else {
      exited_unreaped = true;
    }
  }
  fds.push_back({wake_.fd(), POLLIN, 0});
  // A worker whose stdout closed is reaped soon; a running one is checked for its limits every 100 ms.
  const auto wait = std::min<std::chrono::milliseconds>(timeout, std::chrono::milliseconds(exited_unreaped ? 5 : 100));
  ::poll(fds.data(), fds.size(), int(wait.count()));
  if (fds.back().revents) wake_.drain();
  for (std::size_t k = 0; k + 1 < fds.size(); ++k) {
    if (!fds[k].revents) continue;
    Run& r = runs_.at(ids[k]);
    char buf[4096];
    ssize_t n;
    while ((n = ::read(r.out_fd, buf, sizeof buf)) > 0) r.out.append(buf, std::size_t(n));
    ExecutorEvent e;
    e.job_id = ids[k];
    e.kind = ExecutorEvent::Kind::progress;
    if (r.garbage.empty()) {
      const ProgressRead read = read_progress_lines(r.out, e.progress, e.stage);
      if (!read.garbage.empty() && !r.terminating) {
        r.garbage = read.garbage;
        kill_child(r.pid, SIGKILL);
      } else if (read.found && !r.terminating) {
        events.push_back(e);
      }
    } else {
      r.out.clear();  // stopped for its garbage: the rest is not read
    }
    if (n == 0) {
      ::close(r.out_fd);
      r.out_fd = -1;
    }
  }
  check(events);
  return events;
}

void LocalExecutor::shutdown() {
  for (auto& [id, r] : runs_) {
    if (r.pid > 0) {
      kill_child(r.pid, SIGKILL);
      ::waitpid(r.pid, nullptr, 0);
    }
    if (r.out_fd >= 0) ::close(r.out_fd);
  }
  runs_.clear();
}

}  // namespace cgview::server
