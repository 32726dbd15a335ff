#include "jobs/scheduler.h"

#include "sandbox.h"

#include <algorithm>
#include <chrono>

#include "auth.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "jobs/executor_registry.h"
#include "jobs/job_files.h"
#include "jobs/worker_result.h"
#include "jobs/artifact_files.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

JobScheduler::JobScheduler(MeshService& meshes, JobConfig config)
    : meshes_(meshes),
      config_(std::move(config)),
      admission_(meshes_, config_.worker),
      store_(meshes_.store().data_dir()),
      executor_(make_executor(config_)) {
  std::error_code ec;
  fs::create_directories(meshes_.store().data_dir() / "jobs", ec);
  fs::create_directories(meshes_.store().data_dir() / "runs", ec);
  fs::permissions(meshes_.store().data_dir() / "runs", fs::perms::owner_all, ec);
  // A job's directories in block groups of their own, not in the data
  // directory's (jobs/job_files.h).
  for (const char* d : {"jobs", "runs"}) spread_subdirectories(meshes_.store().data_dir() / d);
  load();
}

void JobScheduler::start() {
  if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
}

JobScheduler::~JobScheduler() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  executor_->wake();
  if (thread_.joinable()) thread_.join();
  executor_->shutdown();
}

fs::path JobScheduler::job_dir(const std::string& id) const { return meshes_.store().data_dir() / "jobs" / id; }

fs::path JobScheduler::run_dir(const std::string& id) const { return meshes_.store().data_dir() / "runs" / id; }

WorkerLimits JobScheduler::limits_of_workers() const {
  WorkerLimits l{config_.timeout_s, config_.memory_mb};
  if (executor_->sandboxed()) {
    l.sandboxed = true;
    l.processes = config_.sandbox->config().processes;
    l.file_mb = config_.sandbox->config().file_mb;
  }
  return l;
}

double JobScheduler::effective_timeout(const Job& j) const {
  if (j.timeout_s <= 0) return config_.timeout_s;
  return config_.timeout_s > 0 ? std::min(j.timeout_s, config_.timeout_s) : j.timeout_s;
}

LaunchSpec JobScheduler::spec(const Job& j) const {
  LaunchSpec s;
  s.job_id = j.id;
  s.name = "cgview-" + j.id;
  s.dir = run_dir(j.id);
  s.work = s.dir / "work";
  s.timeout_s = effective_timeout(j);
  s.memory_mb = config_.memory_mb;
  s.cpus = std::max(1, config_.cpus);
  s.data_dir = meshes_.store().data_dir();
  return s;
}

void JobScheduler::load() {
  std::vector<std::shared_ptr<Job>> unsized, restarted;
  for (auto& j : store_.load()) {
    seq_ = std::max(seq_, j->seq);
    jobs_[j->id] = j;
    order_.push_back(j->id);
    if (!active(j->state)) {
      // Sized once (walking its directory), then stored: later starts read the column.
      if (j->in_flight) {
        j->in_flight = false;
        j->bytes = dir_bytes(job_dir(j->id));
        unsized.push_back(j);
      }
      if (j->state == JobState::done && !j->cached && !j->cache_key.empty()) cache_[j->cache_key] = j->id;
      continue;
    }
    // Still with its executor (a Slurm job by its id): followed again as it was.
    if (!j->handle.empty() && j->executor == executor_->name() && executor_->adopt(spec(*j), j->handle)) {
      j->in_flight = true;
      in_flight_.insert(j->id);
      continue;
    }
    j->in_flight = false;
    j->progress = 0;
    j->stage.clear();
    j->started.clear();
    j->handle.clear();
    j->where.clear();
    if (config_.requeue_on_restart) {
      j->state = JobState::queued;
      queue_.push(j->owner, j->id);
    } else {
      j->error = std::string("the server stopped while the job was ") + to_string(j->state);
      j->state = JobState::interrupted;
      j->finished = now_iso8601();
      j->bytes = dir_bytes(job_dir(j->id));
    }
    restarted.push_back(j);
  }
  unsized.insert(unsized.end(), restarted.begin(), restarted.end());
  if (!unsized.empty()) store_.put_all(unsized);
  // A directory no job names: an import killed before its row was stored.
  // No user saw it; it goes.
  std::error_code ec;
  std::vector<fs::path> orphans;
  for (const auto& e : fs::directory_iterator(meshes_.store().data_dir() / "jobs", ec))
    if (!jobs_.count(e.path().filename().string())) orphans.push_back(e.path());
  // A run no job follows any more: what it left is not read.
  for (const auto& e : fs::directory_iterator(meshes_.store().data_dir() / "runs", ec))
    if (!in_flight_.count(e.path().filename().string())) orphans.push_back(e.path());
  for (const fs::path& p : orphans) fs::remove_all(p, ec);
}

void JobScheduler::save(const Job& j) {
  if (j.deleted) return;  // its row is gone already
  try {
    store_.put(j);
    unsaved_.erase(j.id);
  } catch (const std::exception&) {
    unsaved_.insert(j.id);
  }
}

json JobScheduler::submit(const json& req, const Caller& caller, std::vector<std::string>* new_meshes, bool system) {
  auto j = std::make_shared<Job>(admission_.admit(req, caller, *this, new_meshes, system));
  const std::string& owner = caller.user;
  j->id = new_id();
  j->created = now_iso8601();
  if (system && req.value("timeout_s", json()).is_number())
    j->timeout_s = std::max(1.0, req["timeout_s"].get<double>());
  const UserLimits quota = limits(caller);
  const Usage use = quota.storage_bytes ? usage(owner) : Usage{};
  json out;
  {
    std::lock_guard lock(mutex_);
    j->seq = ++seq_;
    if (const auto hit = cache_.find(j->cache_key); hit != cache_.end()) {
      const Job& o = *jobs_.at(hit->second);
      if (o.state == JobState::done && fs::exists(job_dir(o.files) / "result.json")) {
        j->state = JobState::done;
        j->cached = true;
        j->progress = 1;
        j->stage = "done";
        j->started = j->finished = j->created;
        j->run_s = o.run_s;
        j->artifacts = o.artifacts;
        j->warnings = o.warnings;
        j->files = o.files;
      }
    }
    // A cached result runs nothing and stores nothing: only a job that runs counts.
    if (!j->cached) {
      check_jobs(quota, {0, active_locked(owner)});
      check_room_for_results(quota, use);
    }
    store_.put(*j);
    jobs_[j->id] = j;
    order_.push_back(j->id);
    if (!j->cached) queue_.push(owner, j->id);
    out = job_json(*j);
  }
  if (j->cached) {
    if (on_event) on_event({{"type", "job_done"}, {"job", out}}, Access{owner});
  } else {
    executor_->wake();
  }
  return out;
}

std::optional<json> JobScheduler::cancel(const std::string& id, const Caller& caller) {
  json out;
  bool changed = false, stop_worker = false;
  {
    std::lock_guard lock(mutex_);
    const auto it = jobs_.find(id);
    if (it == jobs_.end() || !readable(*it->second, caller)) return std::nullopt;
    Job& j = *it->second;
    if (!Access{j.owner}.owned_by(caller))
      throw Forbidden("job " + id + " is " + j.owner + "'s: only its owner cancels it");
    if (active(j.state)) {
      // Queued here: out of the queue.  With the executor (or being handed
      // to it): its worker is stopped, and only its size is new when it ends.
      queue_.remove(j.owner, id);
      stop_worker = in_flight_.count(id) > 0;
      j.cancelled = true;
      j.state = JobState::cancelled;
      j.finished = now_iso8601();
      save(j);
      changed = true;
    }
    out = job_json(j);
  }
  if (stop_worker) executor_->cancel(id);
  if (changed) {
    executor_->wake();
    if (on_event) on_event({{"type", "job_cancelled"}, {"job", out}}, job_access(id));
  }
  return out;
}

JobScheduler::Removal JobScheduler::remove(const std::string& id, const Caller& caller) {
  bool ended = false;
  std::string files;  // the results directory that goes with it ("": none, or another job's still)
  {
    std::lock_guard lock(mutex_);
    const auto it = jobs_.find(id);
    if (it == jobs_.end() || !readable(*it->second, caller)) return {};
    const Job& j = *it->second;
    if (!Access{j.owner}.owned_by(caller))
      throw Forbidden("job " + id + " is " + j.owner + "'s: only its owner deletes it");
    ended = !active(j.state) && !j.in_flight;
    if (ended) {
      files = forget_locked(id);
    } else if (!active(j.state)) {
      // Cancelled, its worker not yet gone: gone for everyone now, forgotten when the worker ends.
      it->second->deleted = true;
      store_.remove(id);
      return {true, std::nullopt};
    }
  }
  if (!ended) return {true, cancel(id, caller)};
  std::error_code ec;
  if (!files.empty()) fs::remove_all(job_dir(files), ec);
  return {true, std::nullopt};
}

std::string JobScheduler::forget_locked(std::string id) {
  const auto it = jobs_.find(id);
  store_.remove(id);
  std::string files = it->second->files.empty() ? id : it->second->files;
  const std::string key = it->second->cache_key;
  jobs_.erase(it);
  if (const auto at = std::find(order_.begin(), order_.end(), id); at != order_.end()) order_.erase(at);
  // Another job answering from the same files keeps them, and the cache with them.
  std::string heir;
  for (const auto& [other, o] : jobs_)
    if (o->files == files) heir = other;
  if (const auto c = cache_.find(key); c != cache_.end() && c->second == id) {
    if (heir.empty()) cache_.erase(c);
    else c->second = heir;
  }
  return heir.empty() ? files : "";
}

std::optional<json> JobScheduler::input_files(const Job& j, std::string* error) const {
  json files = json::object();
  for (const auto& [name, in] : j.inputs.items()) {
    if (in.is_object()) {  // an earlier job's artifact
      try {
        files[name] = artifact_file_locked(in.value("job", ""), in.value("artifact", ""), "").string();
      } catch (const std::exception& e) {
        *error = std::string("input '") + name + "': " + e.what();
        return std::nullopt;
      }
      continue;
    }
    const auto rec = meshes_.store().get_mesh(in.get<std::string>());
    if (!rec) {
      *error = "the mesh " + in.get<std::string>() + " (input '" + name + "') was deleted";
      return std::nullopt;
    }
    files[name] = meshes_.store().blob_file(*rec).string();
  }
  return files;
}

std::optional<LaunchSpec> JobScheduler::prepare(Job& j) {
  // A fresh run directory: nothing an earlier run left (a link as its
  // tmp/, a FIFO) is ever bound or read.
  LaunchSpec s = spec(j);
  std::error_code ec;
  fs::remove_all(s.dir, ec);
  fs::create_directories(s.work, ec);  // under runs/, which only the server's user enters
  const fs::path dir = s.dir;
  const auto files = input_files(j, &j.error);
  if (!files) return std::nullopt;
  json inputs = *files, out = s.work.string();
  if (remote_data()) {
    // The worker's own directory on its node: inputs under in/NAME/, results in out/.
    for (const auto& [name, path] : files->items()) {
      const std::string local = "in/" + name + "/" + fs::path(path.get<std::string>()).filename().string();
      s.remote_inputs[name] = local;
      inputs[name] = local;
    }
    out = "out";
    const std::string url = executor_->capabilities().server_url;
    s.server_url = url.empty() ? server_url_ : url;
    s.token = random_hex(32);
    j.worker_token_sha = sha256_hex(s.token);
  }
  // In the sandbox the job sees its own paths (sandbox.h): the data
  // directory's, and the directories above it, are not its to walk.
  const bool sandboxed = limits_of_workers().sandboxed;
  for (const auto& [name, path] : files->items()) {
    const fs::path file = path.get<std::string>();
    const std::string inside = std::string(kSandboxInputs) + "/" + name + "/" + file.filename().string();
    s.read_only.push_back({file, sandboxed ? inside : file.string()});
    if (sandboxed) inputs[name] = inside;
  }
  if (sandboxed) out = kSandboxJob;
  json spec = {{"algorithm", j.algorithm}, {"params", j.params}, {"inputs", inputs}, {"out", out}};
  // A plugin's algorithm: the worker loads its library first.
  if (j.plugin.is_object()) {
    const std::string library = j.plugin.value("library", "");
    std::error_code lib_ec;
    if (library.empty() || !fs::exists(library, lib_ec)) {
      j.error = "the plugin's library is gone (rebuild the plugin)";
      return std::nullopt;
    }
    if (remote_data()) {
      j.error = "plugins run only where the workers see the data directory (" +
                executor_->capabilities().shared_data_setting + ")";
      return std::nullopt;
    }
    const std::string inside = std::string(kSandboxPlugin) + "/" + fs::path(library).filename().string();
    spec["plugin"] = sandboxed ? inside : library;
    s.read_only.push_back({library, sandboxed ? inside : library});
  }
  s.spec = spec.dump();
  try {
    if (!executor_->capabilities().job_json_in_memory) write_file_bytes(dir / "job.json", s.spec);
  } catch (const DiskFull&) {
    j.error = "the server's storage is full: the job could not start";
    return std::nullopt;
  } catch (const IoError& e) {
    j.error = e.what();
    return std::nullopt;
  }
  return s;
}

bool JobScheduler::requeued_when_lost(const WorkerEnd& how) const {
  return how.how == WorkerEnd::How::lost && executor_->capabilities().requeue_lost;
}

void JobScheduler::end(Job& j, const WorkerEnd* how, std::vector<json>& events, const Collected* collected) {
  in_flight_.erase(j.id);
  j.in_flight = false;
  j.worker_token_sha.clear();  // the worker's token dies with its job
  if (!how) leftovers_.push_back(run_dir(j.id));
  if (j.deleted) {
    if (const std::string files = forget_locked(j.id); !files.empty()) leftovers_.push_back(job_dir(files));
    return;
  }
  j.bytes = collected ? collected->bytes : dir_bytes(job_dir(j.id));
  if (j.cancelled) {  // already cancelled (state, event): only its size is new
    save(j);
    return;
  }
  if (how && requeued_when_lost(*how) && !(collected && collected->stopped)) {
    // Its executor lost it (Slurm purged it, or it went with its node): run it again, by setting.
    j.state = JobState::queued;
    j.progress = 0;
    j.stage = "queued again: " + how->detail;
    j.started.clear();
    j.handle.clear();
    j.where.clear();
    queue_.push(j.owner, j.id);
    save(j);
    events.push_back(progress_event(j));
    return;
  }
  if (how) {
    WorkerOutcome r;
    if (collected) r = collected->outcome;
    else r.error = "its run's results were not read";
    if (r.done) {
      j.state = JobState::done;
      j.artifacts = r.artifacts;
      j.warnings = r.warnings;
      j.files = j.id;
      cache_[j.cache_key] = j.id;
      j.progress = 1;
      j.stage = "done";
    } else {
      j.state = JobState::failed;
      j.error = r.error;
    }
  } else {
    j.state = JobState::failed;  // j.error says why it could not start
  }
  j.finished = now_iso8601();
  if (j.started.empty()) j.started = j.finished;
  if (j.run_from != Clock::time_point{}) j.run_s = std::chrono::duration<double>(Clock::now() - j.run_from).count();
  save(j);
  events.push_back({{"type", j.state == JobState::done ? "job_done" : "job_failed"}, {"job", job_json(j)}});
}

void JobScheduler::apply(const ExecutorEvent& e, std::vector<json>& events, const Collected* collected) {
  const auto it = jobs_.find(e.job_id);
  if (it == jobs_.end() || !in_flight_.count(e.job_id)) return;
  Job& j = *it->second;
  switch (e.kind) {
    case ExecutorEvent::Kind::started:
      if (j.cancelled) return;
      // A job followed again after a restart keeps its start.
      if (j.state != JobState::running || j.started.empty()) j.started = now_iso8601();
      j.run_from = Clock::now();
      j.state = JobState::running;
      j.stage = "starting";
      j.progress = 0;
      j.where = e.node;
      j.last_event = Clock::now();
      save(j);
      events.push_back(progress_event(j));
      return;
    case ExecutorEvent::Kind::waiting: {
      if (j.cancelled) return;
      const std::string stage = e.reason.empty() ? "waiting for the cluster" : "waiting for the cluster: " + e.reason;
      if (stage == j.stage && j.state == JobState::queued) return;
      j.state = JobState::queued;  // a job the cluster requeued (its node failed) waits again
      j.progress = 0;
      j.stage = stage;
      save(j);
      events.push_back(progress_event(j));
      return;
    }
    case ExecutorEvent::Kind::progress:
      if (j.cancelled || j.state != JobState::running) return;
      j.progress = e.progress;
      j.stage = e.stage;
      if (Clock::now() - j.last_event >= std::chrono::milliseconds(100)) {
        j.last_event = Clock::now();
        events.push_back(progress_event(j));
      }
      return;
    case ExecutorEvent::Kind::ended:
      end(j, &e.end, events, collected);
      return;
  }
}

void JobScheduler::loop() {
  std::vector<json> events;  // gathered under the lock, sent outside it
  for (;;) {
    std::vector<LaunchSpec> launching;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) break;
      for (const std::string& id : std::vector<std::string>(unsaved_.begin(), unsaved_.end()))
        if (const auto it = jobs_.find(id); it != jobs_.end()) save(*it->second);
      // Queued jobs go to the executor while it has room, owners in turn; a
      // few dozen a turn, so that a thousand sbatch calls do not hold back
      // the progress and ends of the jobs already running.
      constexpr std::size_t kLaunchesPerTurn = 32;
      while (int(in_flight_.size() + launching.size()) < executor_->capacity() && launching.size() < kLaunchesPerTurn) {
        const auto id = queue_.pop();
        if (!id) break;
        Job& j = *jobs_.at(*id);
        if (auto s = prepare(j)) {
          j.in_flight = true;  // being handed over: a delete now only cancels it
          launching.push_back(std::move(*s));
        } else {
          end(j, nullptr, events);
        }
      }
    }
    // Outside the lock: sbatch may take a while.
    std::vector<std::pair<std::string, std::string>> launched;  // job id, handle or error
    std::vector<bool> ok;
    for (const LaunchSpec& s : launching) {
      try {
        launched.emplace_back(s.job_id, executor_->launch(s));
        ok.push_back(true);
      } catch (const std::exception& e) {
        launched.emplace_back(s.job_id, e.what());
        ok.push_back(false);
      }
    }
    {
      std::lock_guard lock(mutex_);
      for (std::size_t k = 0; k < launched.size(); ++k) {
        Job& j = *jobs_.at(launched[k].first);
        if (!ok[k]) {
          j.error = launched[k].second;
          end(j, nullptr, events);  // cancelled meanwhile: only its size is new
          continue;
        }
        ++workers_started_;
        j.in_flight = true;
        j.executor = executor_->name();
        j.handle = launched[k].second;
        in_flight_.insert(j.id);
        save(j);
        if (j.cancelled) executor_->cancel(j.id);  // cancelled while it was being handed over
      }
    }
    for (auto& e : events)
      if (on_event) on_event(e, job_access(e["job"].value("id", "")));
    events.clear();
    const auto happened = executor_->poll(std::chrono::milliseconds(100));
    check_disk();
    // A run's files are read (and its artifacts copied) outside the lock:
    // a slow or hostile file never holds up another request.
    const auto collected = collect(happened);
    std::vector<fs::path> leftovers;
    {
      std::lock_guard lock(mutex_);
      for (const auto& e : happened) {
        const auto c = collected.find(e.job_id);
        apply(e, events, c == collected.end() ? nullptr : &c->second);
      }
      leftovers.swap(leftovers_);
    }
    for (const fs::path& dir : leftovers) {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  }
}

}  // namespace cgview::server
