// What a run leaves, read outside the jobs' lock: its outcome and its
// artifacts taken into the job's results directory when it ends
// (collect), and its directory's size while it runs (check_disk).  The
// run's directory is the job's, hostile input: jobs/job_files.h reads it.
#include "auth.h"
#include "io/mesh_io.h"
#include "jobs/artifact_files.h"
#include "jobs/job_files.h"
#include "jobs/scheduler.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

std::uint64_t JobScheduler::room_of(const std::string& user) const {
  Caller owner{user, false};
  if (user == "local") owner = Caller::local();
  else if (const auto u = meshes_.store().get_user(user)) owner.admin = u->admin;
  const UserLimits quota = limits(owner);
  if (!quota.storage_bytes) return ~std::uint64_t(0);
  const std::uint64_t used = usage(user).storage_bytes;
  return used < *quota.storage_bytes ? *quota.storage_bytes - used : 0;
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
  for (const auto& [id, owner] : running) {
    const JobDir::Usage u = JobDir(run_dir(id) / "work").usage(kMaxJobNames + 1);
    std::string why;
    if (u.names > kMaxJobNames)
      why = "wrote more than " + std::to_string(kMaxJobNames) + " files, the most a job may have";
    else if (const std::uint64_t room = room_of(owner); u.bytes > room)
      why = "wrote " + std::to_string(u.bytes) + " bytes, more than the " + std::to_string(room) +
            " bytes its owner has left under their storage quota";
    if (why.empty()) continue;
    {
      std::lock_guard lock(mutex_);
      if (!in_flight_.count(id)) continue;
      over_disk_[id] = why;
    }
    executor_->cancel(id);
  }
}

std::map<std::string, JobScheduler::Collected> JobScheduler::collect(const std::vector<ExecutorEvent>& happened,
                                                                     std::vector<std::string>* ended) {
  std::map<std::string, Collected> out;
  for (const ExecutorEvent& e : happened) {
    if (e.kind != ExecutorEvent::Kind::ended) continue;
    Caller owner;
    {
      std::lock_guard lock(mutex_);
      const auto it = jobs_.find(e.job_id);
      if (it == jobs_.end() || !in_flight_.count(e.job_id)) continue;
      ended->push_back(e.job_id);
      if (it->second->cancelled || (requeued_when_lost(e.end) && !over_disk_.count(e.job_id))) continue;
      owner.user = it->second->owner;
    }
    // What its results may take: the room left under its owner's quota.
    WorkerLimits limits = limits_of_workers();
    limits.result_bytes = room_of(owner.user);
    const fs::path run = run_dir(e.job_id);
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
      const fs::path results = job_dir(e.job_id);
      std::string why = take_artifacts(work_dir, c.outcome.artifacts, results);
      if (why.empty()) {
        try {
          write_file_bytes(results / "result.json",
                           json{{"artifacts", c.outcome.artifacts}, {"warnings", c.outcome.warnings}}.dump());
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
      fs::create_directories(job_dir(e.job_id), ec);
      try {
        write_file_bytes(job_dir(e.job_id) / "stderr.txt", *err);
      } catch (const std::exception&) {
      }
    }
    out.emplace(e.job_id, std::move(c));
  }
  return out;
}

}  // namespace cgview::server
