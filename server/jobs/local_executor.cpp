#include "jobs/local_executor.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "child_process.h"
#include "core/errors.h"
#include "core/threads.h"
#include "io/mesh_io.h"
#include "jobs/job_files.h"

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
      max_workers_(max_workers > 0 ? max_workers : thread_count()),
      sandbox_(std::move(sandbox)) {}

LocalExecutor::~LocalExecutor() { shutdown(); }

namespace {

// job.json's text in memory (a sealed memfd, read from its start): what
// bubblewrap copies into the sandbox.  -1 where it cannot be made.
int spec_in_memory_fd(const std::string& spec) {
  const int fd = ::memfd_create("job.json", MFD_CLOEXEC | MFD_ALLOW_SEALING);
  if (fd < 0) return -1;
  // Sealed: whoever else holds it can neither change nor grow it.
  if (write_all(fd, spec) != 0 || ::lseek(fd, 0, SEEK_SET) != 0 ||
      ::fcntl(fd, F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_WRITE | F_SEAL_SEAL) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

}  // namespace

LocalExecutor::Started LocalExecutor::start_worker(const LaunchSpec& job, int stdin_fd, bool in_memory) {
  in_memory = in_memory && sandboxed();
  int fds[2], err[2] = {-1, -1};
  if (::pipe2(fds, O_CLOEXEC) != 0) throw LaunchError("pipe failed");
  if (in_memory && ::pipe2(err, O_CLOEXEC) != 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw LaunchError("pipe failed");
  }
  auto close_all = [&] {
    for (int fd : {fds[0], fds[1], err[0], err[1]})
      if (fd >= 0) ::close(fd);
  };
  ChildOptions child;
  child.memory_mb = job.memory_mb;
  child.stdin_fd = stdin_fd;
  child.stdout_fd = fds[1];
  if (in_memory) child.stderr_fd = err[1];
  else child.stderr_file = job.dir / "stderr.txt";  // in the run's directory, out of the job's reach
  child.clean_env = true;
  child.end_with_server = true;
  const std::vector<std::string> argv = {worker_.string(), (job.dir / "job.json").string()};
  Started s;
  if (sandboxed()) {
    s.slot = sandbox_->take_slot();
    const int spec_fd = in_memory ? spec_in_memory_fd(job.spec) : -1;
    Sandbox::Command c;
    try {
      if (in_memory && spec_fd < 0) throw LaunchError(std::string("cannot hold job.json: ") + std::strerror(errno));
      c = sandboxed_worker(*sandbox_, job, worker_, s.slot.number(), child, spec_fd);
    } catch (const std::exception& e) {
      close_all();
      if (spec_fd >= 0) ::close(spec_fd);
      throw LaunchError(e.what());
    }
    s.pid = spawn_child(c.argv, c.options);
    if (spec_fd >= 0) ::close(spec_fd);  // the child holds its own (it has exec'd: spawn_child)
  } else {
    s.pid = spawn_child(argv, child);
  }
  ::close(fds[1]);
  if (err[1] >= 0) ::close(err[1]);
  fds[1] = err[1] = -1;
  if (s.pid < 0) {
    close_all();
    throw LaunchError("fork failed");
  }
  ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
  s.out_fd = fds[0];
  if (err[0] >= 0) ::fcntl(err[0], F_SETFL, O_NONBLOCK);
  s.err_fd = err[0];
  return s;
}

void LocalExecutor::read_stderr(Run& r) {
  char buf[16384];
  ssize_t n = -1;
  while (r.err_fd >= 0 && ((n = ::read(r.err_fd, buf, sizeof buf)) > 0 || (n < 0 && errno == EINTR)))
    if (n > 0 && r.err.size() < kMaxReportBytes)
      r.err.append(buf, std::min(std::size_t(n), std::size_t(kMaxReportBytes) - r.err.size()));
  if (r.err_fd >= 0 && n == 0) {
    ::close(r.err_fd);
    r.err_fd = -1;
  }
}

bool LocalExecutor::start_warm(const LaunchSpec& like) {
  Warm w;
  w.dir = like.dir.parent_path() / ("warm-" + std::to_string(++warms_));
  w.memory_mb = like.memory_mb;
  std::error_code ec;
  fs::remove_all(w.dir, ec);
  for (const char* d : {"work", "in", "plugin"}) fs::create_directories(w.dir / d, ec);
  if (ec) return false;  // the next job starts a worker of its own
  LaunchSpec s = like;
  s.dir = w.dir;
  s.work = w.dir / "work";
  s.read_only = {{w.dir / "in", kSandboxInputs}, {w.dir / "plugin", kSandboxPlugin}};
  int go[2];
  if (::pipe2(go, O_CLOEXEC) != 0) return false;
  try {
    write_file_bytes(w.dir / "job.json", "");  // the file its sandbox binds; hand_over fills it
    w.worker = start_worker(s, go[0]);
  } catch (const std::exception&) {
    ::close(go[0]);
    ::close(go[1]);
    fs::remove_all(w.dir, ec);
    return false;
  }
  ::close(go[0]);
  w.go_fd = go[1];
  warm_.push_back(std::move(w));
  return true;
}

bool LocalExecutor::ready(Warm& w) {
  char buf[4096];
  for (ssize_t n; (n = ::read(w.worker.out_fd, buf, sizeof buf)) > 0;) w.out.append(buf, std::size_t(n));
  return w.out.find(kWorkerReady) != std::string::npos;
}

bool LocalExecutor::hand_over(Warm& w, const LaunchSpec& job) {
  std::error_code ec;
  auto unlink_all = [&] {
    for (const char* d : {"in", "plugin"})
      for (const auto& e : fs::directory_iterator(w.dir / d, ec)) fs::remove_all(e.path(), ec);
    return false;
  };
  // Its inputs and plugin, where it sees them: links (the same file, on the
  // data directory's file system), in directories its sandbox binds read-only.
  if (sandboxed())
    for (const auto& [file, inside] : job.read_only) {
      fs::path link;
      for (const auto& [under, dir] : {std::pair{kSandboxInputs, "in"}, std::pair{kSandboxPlugin, "plugin"}})
        if (const std::string u = std::string(under) + "/"; inside.starts_with(u))
          link = w.dir / dir / inside.substr(u.size());
      if (link.empty()) return unlink_all();
      fs::create_directories(link.parent_path(), ec);
      fs::create_hard_link(file, link, ec);
      if (ec) return unlink_all();
    }
  // Its job.json, into the file it was given (its sandbox binds that file).
  try {
    const std::string& spec = job.spec;
    const int fd = ::open((w.dir / "job.json").c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) return unlink_all();
    const bool whole = write_all(fd, spec) == 0;
    ::close(fd);
    if (!whole) return unlink_all();
  } catch (const std::exception&) {
    return unlink_all();
  }
  fs::rename(w.dir / "stderr.txt", job.dir / "stderr.txt", ec);  // its open file goes along
  return true;
}

bool LocalExecutor::go(Run& r) {
  // Its directory becomes the run's (the scheduler made it, empty): only
  // now, as bubblewrap binds it by its name while it sets the sandbox up.
  if (sandboxed()) {
    std::error_code ec;
    fs::rename(r.warm_dir / "work", r.work, ec);
    if (ec) {
      r.garbage = "the worker started ahead of the job could not be given the run's directory: " + ec.message();
      kill_child(r.pid, SIGKILL);
      return false;
    }
  }
  ::close(r.go_fd);
  r.go_fd = -1;
  return true;
}

void LocalExecutor::go_when_ready(Run& r) {
  if (r.go_fd < 0) return;
  if (const auto at = r.out.find(kWorkerReady); at != std::string::npos) {
    r.out.erase(at, kWorkerReady.size());
    go(r);
  }
}

void LocalExecutor::drop_warm(Warm& w) {
  kill_child(w.worker.pid, SIGKILL);
  ::waitpid(w.worker.pid, nullptr, 0);
  if (w.go_fd >= 0) ::close(w.go_fd);
  ::close(w.worker.out_fd);
  std::error_code ec;
  fs::remove_all(w.dir, ec);
}

std::string LocalExecutor::launch(const LaunchSpec& job) {
  Run r;
  // A worker ahead that is ready and fits (one that died waiting, or was
  // started for another memory limit, goes).
  auto warm = warm_.end();
  for (auto it = warm_.begin(); it != warm_.end();) {
    if (exited(it->worker.pid) || it->memory_mb != job.memory_mb) {
      drop_warm(*it);
      it = warm_.erase(it);
      continue;
    }
    if (warm == warm_.end() && ready(*it)) warm = it;
    ++it;
  }
  if (warm != warm_.end() && hand_over(*warm, job)) {
    // What it wrote before counts as its job's output.
    r.pid = warm->worker.pid;
    r.slot = std::move(warm->worker.slot);
    r.out_fd = warm->worker.out_fd;
    r.out = std::move(warm->out);
    r.go_fd = warm->go_fd;
    r.warm_dir = warm->dir;
    r.work = job.work;
    warm_.erase(warm);
    go_when_ready(r);
  } else {
    Started s = start_worker(job, -1, true);
    r.pid = s.pid;
    r.slot = std::move(s.slot);
    r.out_fd = s.out_fd;
    r.err_fd = s.err_fd;
    r.dir = job.dir;
  }
  watch(job.job_id, job.timeout_s);
  const pid_t pid = r.pid;
  runs_[job.job_id] = std::move(r);
  ExecutorEvent e;
  e.job_id = job.job_id;
  e.kind = ExecutorEvent::Kind::started;
  pending_.push_back(e);
  // The next job's worker, at once: it starts while this one runs, and is
  // ready when the next job comes (one that found none ready would start
  // its own, which is what costs).
  warm_like_ = job;  // workers ahead are started for its like when nothing waits to be said (poll)
  return std::to_string(pid);
}

void LocalExecutor::check(std::vector<ExecutorEvent>& events) {
  const std::set<std::string> cancels = take_cancels(), over = overdue();
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
    if (!r.terminating && !r.timed_out && over.count(it->first)) {
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
      // What it left in its stderr pipe (no writer is left: its sandbox's
      // processes went with their namespace's first), where it is read.
      read_stderr(r);
      if (r.err_fd >= 0) ::close(r.err_fd);
      if (!r.err.empty()) {
        try {
          write_file_bytes(r.dir / "stderr.txt", r.err);
        } catch (const std::exception&) {  // a full disk: the job's message goes without it
        }
      }
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
      if (!r.warm_dir.empty()) used_warm_dirs_.push_back(r.warm_dir);
      if (r.go_fd >= 0) ::close(r.go_fd);
      unwatch(it->first);
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
  // Not before a job's end is said: the removal of the directories
  // pre-started workers left, and starting the workers ahead (while a job
  // runs, they would take its CPU).
  else {
    std::error_code ec;
    for (const fs::path& d : used_warm_dirs_) fs::remove_all(d, ec);
    used_warm_dirs_.clear();
    // Only with a worker's place free: a full executor has jobs waiting (a
    // burst), which start their own workers; one ahead would only take
    // their CPU.
    while (warm_like_ && int(runs_.size()) < max_workers_ && warm_.size() < kWorkersAhead && start_warm(*warm_like_)) {
    }
  }
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
  // The stderr pipes after them (read as they fill: a worker that writes
  // more than a pipe holds waits for it).
  const std::size_t outs = fds.size();
  for (const auto& [id, r] : runs_)
    if (r.err_fd >= 0) {
      fds.push_back({r.err_fd, POLLIN, 0});
      ids.push_back(id);
    }
  fds.push_back({wake_fd(), POLLIN, 0});
  // A worker whose stdout closed is reaped soon; a running one is checked for its limits every 100 ms.
  const auto wait = std::min<std::chrono::milliseconds>(timeout, std::chrono::milliseconds(exited_unreaped ? 5 : 100));
  ::poll(fds.data(), fds.size(), int(wait.count()));
  if (fds.back().revents) drain_wake();
  for (std::size_t k = outs; k + 1 < fds.size(); ++k)
    if (fds[k].revents) read_stderr(runs_.at(ids[k]));
  for (std::size_t k = 0; k < outs; ++k) {
    if (!fds[k].revents) continue;
    Run& r = runs_.at(ids[k]);
    char buf[4096];
    ssize_t n;
    while ((n = ::read(r.out_fd, buf, sizeof buf)) > 0) r.out.append(buf, std::size_t(n));
    go_when_ready(r);
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
  for (Warm& w : warm_) drop_warm(w);
  warm_.clear();
  warm_like_.reset();
  for (auto& [id, r] : runs_) {
    if (r.pid > 0) {
      kill_child(r.pid, SIGKILL);
      ::waitpid(r.pid, nullptr, 0);
    }
    if (r.out_fd >= 0) ::close(r.out_fd);
    if (r.err_fd >= 0) ::close(r.err_fd);
    if (r.go_fd >= 0) ::close(r.go_fd);
    unwatch(id);
  }
  runs_.clear();
}

}  // namespace cgview::server
