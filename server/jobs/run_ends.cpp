// What a run leaves, read outside the jobs' lock: its outcome and its
// artifacts taken into the job's results directory when it ends
// (collect), and its directory's size while it runs (check_disk).  The
// run's directory is the job's, hostile input: jobs/job_files.h reads it.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "auth.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "jobs/artifact_files.h"
#include "jobs/job_files.h"
#include "jobs/scheduler.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

namespace {

// `text` written over the file at `path` (the server's, which nothing else
// writes), in place: no new file.
void rewrite(const fs::path& path, const std::string& text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC | O_NOFOLLOW | O_CLOEXEC);
  int err = fd < 0 ? errno : write_all(fd, text);
  if (fd >= 0 && ::close(fd) != 0 && !err) err = errno;
  if (err == ENOSPC || err == EDQUOT) throw DiskFull(path.string() + ": " + std::strerror(err));
  if (err) throw IoError(path.string() + ": cannot write: " + std::strerror(err));
}

}  // namespace

std::uint64_t JobScheduler::room_of(const std::string& user) const {
  Caller owner{user, false};
  if (user == "local") owner = Caller::local();
  else if (const auto u = meshes_.store().get_user(user)) owner.admin = u->admin;
  const UserLimits quota = limits(owner);
  if (!quota.storage_bytes) return room_left(quota, {});  // no limit: its use need not be added up
  return room_left(quota, usage(user));
}

void JobScheduler::check_disk() {
  constexpr auto kEvery = std::chrono::seconds(2);
  if (remote_data() || Clock::now() - last_disk_check_ < kEvery) return;
  last_disk_check_ = Clock::now();
  std::vector<std::pair<std::string, std::string>> running;  // id, owner
  {
    std::lock_guard lock(mutex_);
    for (const std::string& id : in_flight_)
      if (const auto it = jobs_.find(id); it != jobs_.end() && !it->second->cancelled && !over_disk_.count(id))
        running.emplace_back(id, it->second->owner);
  }
  // An owner's running jobs share the room left under their quota: what one
  // has written, the next may not.
  std::map<std::string, std::uint64_t> room;
  for (const auto& [id, owner] : running) {
    const JobDir::Usage u = JobDir(run_dir(id) / "work").usage(config_.max_files + 1);
    const auto [left, first] = room.try_emplace(owner, 0);
    if (first) left->second = room_of(owner);
    std::string why;
    if (u.names > config_.max_files)
      why = "wrote more than " + std::to_string(config_.max_files) + " files, the most a job may have";
    else if (u.bytes > left->second)
      why = "wrote " + std::to_string(u.bytes) + " bytes, more than the " + std::to_string(left->second) +
            " bytes its owner has left under their storage quota";
    else left->second -= u.bytes;
    if (why.empty()) continue;
    {
      std::lock_guard lock(mutex_);
      if (!in_flight_.count(id)) continue;
      over_disk_[id] = why;
    }
    executor_->cancel(id);
  }
}

std::map<std::string, JobScheduler::Collected> JobScheduler::collect(const std::vector<ExecutorEvent>& happened) {
  std::map<std::string, Collected> out;
  for (const ExecutorEvent& e : happened) {
    if (e.kind != ExecutorEvent::Kind::ended) continue;
    std::optional<std::string> owner;  // nullopt: nothing of the run is read (cancelled, or to run again)
    {
      std::lock_guard lock(mutex_);
      const auto it = jobs_.find(e.job_id);
      if (it == jobs_.end() || !in_flight_.count(e.job_id)) continue;
      if (!it->second->cancelled && !(requeued_when_lost(e.end) && !over_disk_.count(e.job_id)))
        owner = it->second->owner;
    }
    if (owner) out.emplace(e.job_id, collect_run(e, *owner));
    // Gone before the job says it ended: a job seen ended has no run left.
    std::error_code ec;
    fs::remove_all(run_dir(e.job_id), ec);
  }
  return out;
}

JobScheduler::Collected JobScheduler::collect_run(const ExecutorEvent& e, const std::string& owner) {
  // What its results may take: the room left under its owner's quota.
  WorkerLimits limits = limits_of_workers();
  limits.result_bytes = room_of(owner);
  {
    std::lock_guard lock(mutex_);
    if (const auto it = jobs_.find(e.job_id); it != jobs_.end()) limits.timeout_s = effective_timeout(*it->second);
  }
  const fs::path run = run_dir(e.job_id), results = job_dir(e.job_id);
  const JobDir work_dir(run / "work"), run_files(run);
  Collected c{read_worker_outcome(work_dir, run_files, e.end, limits)};
  {
    std::lock_guard lock(mutex_);
    if (const auto over = over_disk_.find(e.job_id); over != over_disk_.end()) {
      c.outcome = WorkerOutcome{};
      c.outcome.error = over->second;
      c.stopped = true;
      over_disk_.erase(over);
    }
  }
  if (c.outcome.done) {
    std::string why = take_artifacts(work_dir, c.outcome.artifacts, results, executor_->capabilities().run_ends_whole);
    if (why.empty()) {
      try {
        const std::string result = json{{"artifacts", c.outcome.artifacts}, {"warnings", c.outcome.warnings}}.dump();
        // Where the run ended whole, the worker's result.json (read above)
        // is moved beside the artifacts and the server's written over it:
        // one file fewer made and removed a job.  (The job is not done
        // before this returns: nothing reads the file meanwhile.)
        std::string not_moved;
        if (executor_->capabilities().run_ends_whole &&
            work_dir.move("result.json", results / "result.json", kMaxResultJsonBytes, &not_moved))
          rewrite(results / "result.json", result);
        else write_file_bytes(results / "result.json", result);
      } catch (const std::exception& x) {
        why = x.what();
      }
    }
    // What is kept, side files and list included, is what counts.
    if (const std::uint64_t kept = dir_bytes(results); why.empty() && kept > limits.result_bytes)
      why = "its results take " + std::to_string(kept) + " bytes, more than the " +
            std::to_string(limits.result_bytes) + " bytes its owner has left under their storage quota";
    if (!why.empty()) {
      std::error_code ec;
      fs::remove_all(results, ec);
      c.outcome.done = false;
      c.outcome.error = "the job's results could not be kept: " + why;
    }
  }
  // The start of its stderr (what a plugin printed) is kept beside its results.
  std::string why;
  if (const auto err = run_files.read("stderr.txt", kMaxReportBytes, &why, true); err && !err->empty()) {
    std::error_code ec;
    fs::create_directories(results, ec);
    try {
      write_file_bytes(results / "stderr.txt", *err);
    } catch (const std::exception&) {
    }
  }
  c.bytes = dir_bytes(results);
  return c;
}

}  // namespace cgview::server
