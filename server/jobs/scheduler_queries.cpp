// The scheduler's read side: who sees which job, counts and usage for the
// metrics and quotas, and a done job's artifacts.
#include "core/errors.h"
#include "jobs/scheduler.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

int JobScheduler::active_locked(const std::string& owner) const {
  int n = 0;
  for (const auto& [id, j] : jobs_) n += j->owner == owner && active(j->state);
  return n;
}

JobCounts JobScheduler::counts() const {
  JobCounts c;
  std::lock_guard lock(mutex_);
  for (const auto& [id, j] : jobs_) {
    ++c.by_state_algorithm[{to_string(j->state), j->algorithm}];
    c.artifact_bytes += j->bytes;
  }
  c.queued = queue_.size();
  for (const auto& id : in_flight_) {
    const JobState s = jobs_.at(id)->state;
    c.queued += s == JobState::queued;
    c.running += s == JobState::running;
  }
  return c;
}

Usage JobScheduler::usage(const std::string& user) const {
  Usage u;
  u.storage_bytes = meshes_.store().mesh_bytes(user);
  std::lock_guard lock(mutex_);
  for (const auto& [id, j] : jobs_)
    if (j->owner == user) u.storage_bytes += j->bytes;
  u.jobs_active = active_locked(user);
  return u;
}

void JobScheduler::check_storage(const Caller& caller, std::uint64_t adding, const std::string& what) const {
  const UserLimits quota = limits(caller);
  if (quota.storage_bytes) server::check_storage(quota, usage(caller.user), adding, what);
}

void JobScheduler::check_job_count(const Caller& caller) const {
  const UserLimits quota = limits(caller);
  if (quota.concurrent_jobs) check_jobs(quota, usage(caller.user));
}

bool JobScheduler::readable(const Job& j, const Caller& caller) const {
  // Another user's job: the store knows whether it was shared.
  if (j.deleted) return false;
  return Access{j.owner}.allows(caller) || meshes_.store().access("job", j.id, j.owner).allows(caller);
}

const Job& JobScheduler::job_locked(const std::string& id, const Caller& caller) const {
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || !readable(*it->second, caller)) throw std::out_of_range("no job with id '" + id + "'");
  return *it->second;
}

Access JobScheduler::job_access(const std::string& id) const {
  std::string owner;
  {
    std::lock_guard lock(mutex_);
    const auto it = jobs_.find(id);
    if (it != jobs_.end()) owner = it->second->owner;
  }
  return meshes_.store().access("job", id, owner);
}

Access JobScheduler::access(const std::string& id, const Caller& caller) const {
  std::string owner;
  {
    std::lock_guard lock(mutex_);
    owner = job_locked(id, caller).owner;
  }
  return meshes_.store().access("job", id, owner);
}

json JobScheduler::list(const Caller& caller) const {
  std::lock_guard lock(mutex_);
  json list = json::array();
  for (const auto& id : order_)
    if (const Job& j = *jobs_.at(id); readable(j, caller)) list.push_back(job_json(j));
  return {{"jobs", list}};
}

std::optional<json> JobScheduler::get(const std::string& id, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  try {
    return job_json(job_locked(id, caller));
  } catch (const std::out_of_range&) {
    return std::nullopt;
  }
}

fs::path JobScheduler::artifact_file(const std::string& job, const std::string& artifact, const std::string& kind,
                                     const Caller& caller) const {
  std::lock_guard lock(mutex_);
  return artifact_file_locked(job, artifact, kind, caller);
}

fs::path JobScheduler::artifact_file_locked(const std::string& id, const std::string& name, const std::string& kind,
                                            const Caller& caller) const {
  const Job& j = job_locked(id, caller);
  if (j.state != JobState::done)
    throw InvalidInput("job " + id + " is " + to_string(j.state) + ", not done: it has no artifacts");
  for (const auto& a : j.artifacts)
    if (a.value("name", "") == name) {
      if (!kind.empty() && a.value("kind", "") != kind)
        throw InvalidInput("artifact '" + name + "' of job " + id + " is a " + a.value("kind", "") + ", not a " + kind);
      return job_dir(j.files) / a.value("file", "");
    }
  throw std::out_of_range("job " + id + " has no artifact '" + name + "'");
}

std::pair<fs::path, json> JobScheduler::stored_artifact(const std::string& id, const std::string& name,
                                                        const Caller& caller) const {
  std::lock_guard lock(mutex_);
  const Job& j = job_locked(id, caller);
  if (j.state != JobState::done)
    throw InvalidInput("job " + id + " is " + to_string(j.state) + ", not done: it has no artifacts");
  for (const auto& a : j.artifacts)
    if (a.value("name", "") == name) return {job_dir(j.files), a};
  throw std::out_of_range("job " + id + " has no artifact '" + name + "'");
}

namespace {

const ArtifactCodec& codec_of(const json& entry) {
  const ArtifactCodec* codec = artifact_codec(entry.value("kind", ""));
  if (!codec) throw UnsupportedFormat("artifact '" + entry.value("name", "") + "' is of no kind this server knows");
  return *codec;
}

}  // namespace

ExportedArtifact JobScheduler::artifact(const std::string& id, const std::string& name, const std::string& format,
                                        const Caller& caller) {
  const auto [dir, entry] = stored_artifact(id, name, caller);
  std::string mesh_id;
  {
    std::lock_guard lock(mutex_);
    mesh_id = job_locked(id, caller).mesh_id;
  }
  return codec_of(entry).exported(dir, entry, format, [&] {
    const auto rec = meshes_.store().get_mesh(mesh_id);
    if (!rec) throw std::out_of_range("the mesh " + mesh_id + " of job " + id + " was deleted");
    return *meshes_.mesh(*rec);
  });
}

ArtifactValue JobScheduler::artifact_value(const std::string& id, const std::string& name, OutputKind kind,
                                           const Caller& caller) const {
  const auto [dir, entry] = stored_artifact(id, name, caller);
  const ArtifactCodec& codec = codec_of(entry);
  if (codec.kind() != kind)
    throw UnsupportedFormat("artifact '" + name + "' of job " + id + " is a " + entry.value("kind", "") + ", not a " +
                            to_string(kind));
  return codec.load(dir, entry);
}

}  // namespace cgview::server
