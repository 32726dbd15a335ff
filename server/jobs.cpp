#include "jobs.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <fstream>
#include <random>
#include <sstream>

#include "algorithm_json.h"
#include "child_process.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "io/skeleton_io.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "voxel/voxel_io.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

struct JobScheduler::Job {
  std::string id, owner, algorithm, mesh_id, mesh_sha, params = "{}", cache_key;
  std::string inputs = "{}";  // every input by name -> mesh id; mesh_id is the first
  std::string state = "queued", stage, error, created, started, finished, artifacts = "[]", files;
  double progress = 0;
  bool cached = false;
  std::uint64_t bytes = 0;  // of its directory once it ended, stored with it (its owner's quota counts them)
  std::int64_t seq = 0;
  // while running
  pid_t pid = -1;
  int out_fd = -1;
  std::string out_buf;
  Clock::time_point launched, last_event, term_sent;
  bool cancelled = false, timed_out = false;
};

namespace {

std::string read_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

json value_json(const ParamValue& v) {
  return std::visit([](const auto& x) { return json(x); }, v);
}

// The bytes of the files under a directory (0 when there is none).
std::uint64_t dir_bytes(const fs::path& dir) {
  std::uint64_t n = 0;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec)) n += it->file_size(ec);
  return n;
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

}  // namespace

JobScheduler::JobScheduler(MeshService& meshes, JobConfig config) : meshes_(meshes), config_(std::move(config)) {
  if (config_.max_workers <= 0) config_.max_workers = int(std::max(1u, std::thread::hardware_concurrency()));
  // What the worker can run (the test worker has a few more, hidden).
  {
    const std::string cmd = "'" + config_.worker.string() + "' --list";
    std::string text;
    if (FILE* p = ::popen(cmd.c_str(), "r")) {
      char buf[4096];
      for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) text.append(buf, n);
      ::pclose(p);
    }
    const json list = json::parse(text, nullptr, false);
    if (list.is_array()) {
      for (const auto& a : list)
        if (a.is_object() && a.contains("name")) worker_algorithms_[a["name"].get<std::string>()] = a;
    } else {
      // Serve meshes anyway; jobs will fail with the reason.
      std::fprintf(stderr, "cgview-server: warning: cannot run the job worker %s (--worker); jobs will fail\n",
                   config_.worker.c_str());
      for (const auto& [name, a] : algorithms()) worker_algorithms_[name] = protocol::to_json(a);
    }
  }
  const fs::path dir = meshes_.store().data_dir();
  std::error_code ec;
  fs::create_directories(dir / "jobs", ec);
  db_ = open_database(dir / "cgview.db");
  exec_sql(db_,
           "CREATE TABLE IF NOT EXISTS jobs ("
           " id TEXT PRIMARY KEY, seq INTEGER NOT NULL, owner TEXT NOT NULL, algorithm TEXT NOT NULL,"
           " mesh_id TEXT NOT NULL, mesh_sha TEXT NOT NULL, params TEXT NOT NULL, cache_key TEXT NOT NULL,"
           " state TEXT NOT NULL, stage TEXT NOT NULL, progress REAL NOT NULL, error TEXT NOT NULL,"
           " cached INTEGER NOT NULL, created TEXT NOT NULL, started TEXT NOT NULL, finished TEXT NOT NULL,"
           " artifacts TEXT NOT NULL, files TEXT NOT NULL, inputs TEXT NOT NULL DEFAULT '{}', bytes INTEGER);"
           "CREATE INDEX IF NOT EXISTS jobs_cache ON jobs(cache_key);",
           "jobs");
  // A database from before algorithms of several inputs lacks the column.
  add_missing_column(db_, "jobs", "inputs", "TEXT NOT NULL DEFAULT '{}'", "jobs");
  // One from before result sizes were stored: NULL until load sizes the job once.
  add_missing_column(db_, "jobs", "bytes", "INTEGER", "jobs");
  load();
  if (::pipe2(wake_pipe_, O_CLOEXEC | O_NONBLOCK) != 0) throw IoError("jobs: pipe failed");
}

void JobScheduler::start() {
  if (!thread_.joinable()) thread_ = std::thread([this] { loop(); });
}

JobScheduler::~JobScheduler() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake();
  if (thread_.joinable()) thread_.join();
  ::close(wake_pipe_[0]);
  ::close(wake_pipe_[1]);
  sqlite3_close(db_);
}

fs::path JobScheduler::job_dir(const std::string& id) const { return meshes_.store().data_dir() / "jobs" / id; }

void JobScheduler::wake() {
  const char c = 1;
  [[maybe_unused]] auto n = ::write(wake_pipe_[1], &c, 1);
}

void JobScheduler::load() {
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db_,
                     "SELECT id, seq, owner, algorithm, mesh_id, mesh_sha, params, cache_key, state, stage, progress,"
                     " error, cached, created, started, finished, artifacts, files, inputs, bytes FROM jobs ORDER BY seq",
                     -1, &s, nullptr);
  auto text = [&](int c) {
    const auto* p = sqlite3_column_text(s, c);
    return p ? std::string(reinterpret_cast<const char*>(p)) : std::string();
  };
  std::vector<std::shared_ptr<Job>> restart, unsized;
  while (sqlite3_step(s) == SQLITE_ROW) {
    auto j = std::make_shared<Job>();
    j->id = text(0);
    j->seq = sqlite3_column_int64(s, 1);
    j->owner = text(2);
    j->algorithm = text(3);
    j->mesh_id = text(4);
    j->mesh_sha = text(5);
    j->params = text(6);
    j->cache_key = text(7);
    j->state = text(8);
    j->stage = text(9);
    j->progress = sqlite3_column_double(s, 10);
    j->error = text(11);
    j->cached = sqlite3_column_int(s, 12) != 0;
    j->created = text(13);
    j->started = text(14);
    j->finished = text(15);
    j->artifacts = text(16);
    j->files = text(17);
    j->inputs = text(18);
    const bool ended = j->state != "queued" && j->state != "running";
    if (sqlite3_column_type(s, 19) != SQLITE_NULL) j->bytes = std::uint64_t(sqlite3_column_int64(s, 19));
    else if (ended) unsized.push_back(j);
    seq_ = std::max(seq_, j->seq);
    jobs_[j->id] = j;
    order_.push_back(j->id);
    if (!ended) restart.push_back(j);
    if (j->state == "done" && !j->cached) cache_[j->cache_key] = j->id;
  }
  sqlite3_finalize(s);
  // Sized once (walking its directory), then stored: later starts read the column.
  if (!unsized.empty()) {
    exec_sql(db_, "BEGIN", "jobs");
    try {
      for (auto& j : unsized) {
        j->bytes = dir_bytes(job_dir(j->id));
        persist(*j);
      }
    } catch (...) {
      exec_sql(db_, "ROLLBACK", "jobs");
      throw;
    }
    exec_sql(db_, "COMMIT", "jobs");
  }
  for (auto& j : restart) {
    j->progress = 0;
    j->stage.clear();
    j->started.clear();
    if (config_.requeue_on_restart) {
      j->state = "queued";
      queues_[j->owner].push_back(j->id);
    } else {
      j->error = "the server stopped while the job was " + j->state;
      j->state = "interrupted";
      j->finished = now_iso8601();
      j->bytes = dir_bytes(job_dir(j->id));
    }
    persist(*j);
  }
}

void JobScheduler::persist(const Job& j) {
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db_,
                         "INSERT OR REPLACE INTO jobs (id, seq, owner, algorithm, mesh_id, mesh_sha, params, cache_key,"
                         " state, stage, progress, error, cached, created, started, finished, artifacts, files, inputs, bytes)"
                         " VALUES (?1,?2,?3,?4,?5,?6,?7,?8,?9,?10,?11,?12,?13,?14,?15,?16,?17,?18,?19,?20)",
                         -1, &s, nullptr) != SQLITE_OK)
    throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
  int i = 0;
  auto t = [&](const std::string& v) { sqlite3_bind_text(s, ++i, v.data(), int(v.size()), SQLITE_TRANSIENT); };
  t(j.id);
  sqlite3_bind_int64(s, ++i, j.seq);
  t(j.owner), t(j.algorithm), t(j.mesh_id), t(j.mesh_sha), t(j.params), t(j.cache_key), t(j.state), t(j.stage);
  sqlite3_bind_double(s, ++i, j.progress);
  t(j.error);
  sqlite3_bind_int(s, ++i, j.cached ? 1 : 0);
  t(j.created), t(j.started), t(j.finished), t(j.artifacts), t(j.files), t(j.inputs);
  // Unsized (NULL) while its worker may still write: a start after a crash
  // sizes it then (a running job cancelled is sized when reaped).
  if (j.state == "queued" || j.state == "running" || j.pid > 0) sqlite3_bind_null(s, ++i);
  else sqlite3_bind_int64(s, ++i, std::int64_t(j.bytes));
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  if (rc == SQLITE_FULL) throw DiskFull(std::string("jobs: ") + sqlite3_errmsg(db_));
  if (rc != SQLITE_DONE) throw IoError(std::string("jobs: ") + sqlite3_errmsg(db_));
}

void JobScheduler::save(const Job& j) {
  try {
    persist(j);
    unsaved_.erase(j.id);
  } catch (const std::exception&) {
    unsaved_.insert(j.id);
  }
}

// Every input by name; a job from before several inputs has only "mesh".
static json job_inputs(const std::string& inputs, const std::string& mesh_id) {
  json in = json::parse(inputs, nullptr, false);
  if (!in.is_object() || in.empty()) in = {{"mesh", mesh_id}};
  return in;
}

json JobScheduler::job_json(const Job& j) const {
  auto opt = [](const std::string& s) { return s.empty() ? json(nullptr) : json(s); };
  json artifacts = json::parse(j.artifacts, nullptr, false);
  if (!artifacts.is_array()) artifacts = json::array();
  for (auto& a : artifacts) a.erase("file");
  return {{"id", j.id},
          {"owner", j.owner},
          {"algorithm", j.algorithm},
          {"inputs", job_inputs(j.inputs, j.mesh_id)},
          {"params", json::parse(j.params, nullptr, false)},
          {"state", j.state},
          {"progress", j.progress},
          {"stage", j.stage},
          {"error", opt(j.error)},
          {"cached", j.cached},
          {"created", j.created},
          {"started", opt(j.started)},
          {"finished", opt(j.finished)},
          {"artifacts", artifacts}};
}

json JobScheduler::algorithms_json() const {
  json list = json::array();
  for (const auto& [name, a] : worker_algorithms_)
    if (a.value("area", "") != "test") list.push_back(a);
  return {{"algorithms", list}};
}

json JobScheduler::submit(const json& req, const Caller& caller, std::vector<std::string>* new_meshes) {
  const std::string& owner = caller.user;
  if (!req.is_object()) throw InvalidInput("the body must be a JSON object");
  if (!req.contains("algorithm") || !req["algorithm"].is_string()) throw InvalidInput("\"algorithm\" must be a string");
  const std::string algorithm = req["algorithm"].get<std::string>();
  if (!worker_algorithms_.count(algorithm)) throw std::out_of_range("no algorithm '" + algorithm + "'");
  const UserLimits quota = limits(caller);
  // Each input the algorithm declares is a stored mesh: its id, or an earlier
  // job's output mesh {"job": id, "artifact": name}.
  const json inputs = req.value("inputs", json::object());
  json specs = worker_algorithms_.at(algorithm).value("inputs", json::array());
  if (specs.empty()) specs = json::array({{{"name", "mesh"}, {"kind", "mesh"}}});
  const auto shape = [](const std::string& name) {
    return "\"inputs\" must be {\"" + name + "\": \"<mesh id>\"} or {\"" + name +
           "\": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}}";
  };
  if (!inputs.is_object()) throw InvalidInput(shape(specs[0].value("name", "mesh")));
  std::string names;
  for (const auto& spec : specs) names += (names.empty() ? "" : ", ") + spec.value("name", "");
  for (const auto& [name, v] : inputs.items()) {
    bool known = false;
    for (const auto& spec : specs) known = known || spec.value("name", "") == name;
    if (!known) throw InvalidInput("algorithm '" + algorithm + "' has no input '" + name + "' (it takes: " + names + ")");
  }
  json resolved = json::object();
  InputSummaries summaries;
  std::string mesh_id, input_shas;
  std::optional<MeshRecord> mesh;
  for (const auto& spec : specs) {
    const std::string name = spec.value("name", ""), kind = spec.value("kind", "mesh");
    if (kind != "mesh") {
      // Any other kind is an earlier job's artifact of that kind.
      if (!inputs.contains(name)) throw InvalidInput("input '" + name + "' is missing: {\"" + name + "\": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}}");
      const json& v = inputs[name];
      if (!v.is_object() || !v.value("job", json()).is_string() || !v.value("artifact", json()).is_string())
        throw InvalidInput("input '" + name + "' is a " + kind + ": {\"job\": \"<job id>\", \"artifact\": \"<name>\"}");
      {
        std::lock_guard lock(mutex_);
        (void)artifact_file_locked(v["job"], v["artifact"], kind, caller);
      }
      resolved[name] = {{"job", v["job"]}, {"artifact", v["artifact"]}};
      input_shas += "\n" + name + "=" + v["job"].get<std::string>() + "/" + v["artifact"].get<std::string>();
      continue;
    }
    if (!inputs.contains(name)) throw InvalidInput("input '" + name + "' is missing: " + shape(name));
    const json& v = inputs[name];
    std::string id;
    if (v.is_string()) {
      id = v.get<std::string>();
    } else if (v.is_object() && v.value("job", json()).is_string() && v.value("artifact", json()).is_string()) {
      // A chain: an earlier job's output mesh becomes a stored mesh (once, by
      // content) and the new job runs on it like on any other.
      const std::string from = v["job"], artifact_name = v["artifact"];
      const ArtifactBytes ply = artifact(from, artifact_name, "ply", caller);
      if (const auto known = meshes_.store().find_by_sha256(sha256_hex(ply.bytes), owner)) id = known->id;
      else {
        // Refused before it stores anything (even where the job would be a cache hit).
        if (quota.concurrent_jobs) check_jobs(quota, usage(owner));
        check_storage(caller, ply.bytes.size(), "the mesh of " + from + "/" + artifact_name);
        id = meshes_.upload(from + "-" + artifact_name + ".ply", "ply", ply.bytes, owner).id;
        if (new_meshes) new_meshes->push_back(id);
      }
    } else {
      throw InvalidInput(shape(name));
    }
    const auto rec = meshes_.store().get_mesh(id, caller);
    if (!rec) throw std::out_of_range("no mesh with id '" + id + "'");
    resolved[name] = id;
    // What a precheck may know of it: the stored report's box and counts.
    const json report = json::parse(rec->report_json, nullptr, false);
    if (report.is_object()) {
      InputSummary& sum = summaries[name];
      sum.vertices = report.value("vertices", std::size_t(0));
      sum.faces = report.value("faces", std::size_t(0));
      const json box = report.value("bbox", json::object());
      if (box.contains("min") && box.contains("max") && box["min"].size() == 3 && box["max"].size() == 3 &&
          box["min"][0].is_number() && box["max"][0].is_number())
        for (int a = 0; a < 3; ++a) {
          sum.bbox.min[a] = box["min"][a].get<double>();
          sum.bbox.max[a] = box["max"][a].get<double>();
        }
    }
    if (!mesh) {
      mesh = rec;
      mesh_id = id;
    } else {
      input_shas += "\n" + name + "=" + rec->sha256;
    }
  }
  const json params_in = req.contains("params") ? req["params"] : json::object();
  // Canonical parameters: checked, every one present (defaults filled in).
  json canonical = json::object();
  const auto& registry = algorithms();
  if (const auto it = registry.find(algorithm); it != registry.end()) {
    const auto values = protocol::params_from_json(it->second, params_in);
    for (const ParamSpec& p : it->second.params) {
      const auto v = values.find(p.name);
      canonical[p.name] = value_json(v == values.end() ? p.default_value : v->second);
    }
    if (const auto in = summaries.find("mesh"); in != summaries.end())
      check_selections(it->second.params, values, in->second.vertices, in->second.faces);
    if (it->second.precheck) it->second.precheck(summaries, values);
  } else {
    // Only the worker knows it (a test algorithm): the worker checks.
    if (!params_in.is_null() && !params_in.is_object()) throw InvalidInput("\"params\" must be a JSON object");
    if (params_in.is_object()) canonical = params_in;
  }
  auto j = std::make_shared<Job>();
  j->id = new_id();
  j->owner = owner;
  j->algorithm = algorithm;
  j->mesh_id = mesh_id;
  j->mesh_sha = mesh ? mesh->sha256 : "";
  j->inputs = resolved.dump();
  j->params = canonical.dump();
  // A one-mesh job keeps the key it always had (its cached results stay valid).
  j->cache_key = sha256_hex((mesh ? mesh->sha256 : std::string()) + input_shas + "\n" + algorithm + "\n" + j->params);
  j->created = now_iso8601();
  const Usage use = quota.storage_bytes ? usage(owner) : Usage{};
  json out, event;
  {
    std::lock_guard lock(mutex_);
    j->seq = ++seq_;
    if (const auto hit = cache_.find(j->cache_key); hit != cache_.end()) {
      const Job& o = *jobs_.at(hit->second);
      if (o.state == "done" && fs::exists(job_dir(o.files) / "result.json")) {
        j->state = "done";
        j->cached = true;
        j->progress = 1;
        j->stage = "done";
        j->started = j->finished = j->created;
        j->artifacts = o.artifacts;
        j->files = o.files;
      }
    }
    // A cached result runs nothing and stores nothing: only a job that runs counts.
    if (!j->cached) {
      check_jobs(quota, {0, active_locked(owner)});
      check_room_for_results(quota, use);
    }
    persist(*j);
    jobs_[j->id] = j;
    order_.push_back(j->id);
    if (!j->cached) queues_[owner].push_back(j->id);
    out = job_json(*j);
  }
  if (j->cached) {
    if (on_event) on_event({{"type", "job_done"}, {"job", out}}, Access{owner});
  } else {
    wake();
  }
  return out;
}

int JobScheduler::active_locked(const std::string& owner) const {
  int n = 0;
  for (const auto& [id, j] : jobs_) n += j->owner == owner && (j->state == "queued" || j->state == "running");
  return n;
}

JobCounts JobScheduler::counts() const {
  JobCounts c;
  std::lock_guard lock(mutex_);
  for (const auto& [id, j] : jobs_) {
    ++c.by_state_algorithm[{j->state, j->algorithm}];
    c.artifact_bytes += j->bytes;
  }
  for (const auto& [owner, q] : queues_) c.queued += q.size();
  c.running = running_ids_.size();
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

bool JobScheduler::readable(const Job& j, const Caller& caller) const {
  // Another user's job: the store knows whether it was shared.
  return Access{j.owner}.allows(caller) || meshes_.store().access("job", j.id, j.owner).allows(caller);
}

const JobScheduler::Job& JobScheduler::job_locked(const std::string& id, const Caller& caller) const {
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

std::optional<json> JobScheduler::cancel(const std::string& id, const Caller& caller) {
  json out;
  bool changed = false;
  {
    std::lock_guard lock(mutex_);
    const auto it = jobs_.find(id);
    if (it == jobs_.end() || !readable(*it->second, caller)) return std::nullopt;
    Job& j = *it->second;
    if (!Access{j.owner}.owned_by(caller)) throw Forbidden("job " + id + " is " + j.owner + "'s: only its owner cancels it");
    if (j.state == "queued") {
      auto& q = queues_[j.owner];
      q.erase(std::remove(q.begin(), q.end(), id), q.end());
      changed = true;
    } else if (j.state == "running") {
      j.cancelled = true;
      if (j.pid > 0) {
        ::kill(j.pid, SIGTERM);
        j.term_sent = Clock::now();
      }
      changed = true;
    }
    if (changed) {
      j.state = "cancelled";
      j.finished = now_iso8601();
      save(j);
    }
    out = job_json(j);
  }
  if (changed) {
    wake();
    if (on_event) on_event({{"type", "job_cancelled"}, {"job", out}}, job_access(id));
  }
  return out;
}

fs::path JobScheduler::artifact_file_locked(const std::string& id, const std::string& name, const std::string& kind,
                                           const Caller& caller) const {
  const Job& j = job_locked(id, caller);
  if (j.state != "done") throw InvalidInput("job " + id + " is " + j.state + ", not done: it has no artifacts");
  for (const auto& a : json::parse(j.artifacts, nullptr, false))
    if (a.value("name", "") == name) {
      if (!kind.empty() && a.value("kind", "") != kind)
        throw InvalidInput("artifact '" + name + "' of job " + id + " is a " + a.value("kind", "") + ", not a " + kind);
      return job_dir(j.files) / a.value("file", "");
    }
  throw std::out_of_range("job " + id + " has no artifact '" + name + "'");
}

ArtifactBytes JobScheduler::artifact(const std::string& id, const std::string& name, const std::string& format_in,
                                     const Caller& caller) {
  json entry;
  std::string files, mesh_id;
  {
    std::lock_guard lock(mutex_);
    const Job& j = job_locked(id, caller);
    if (j.state != "done") throw InvalidInput("job " + id + " is " + j.state + ", not done: it has no artifacts");
    for (const auto& a : json::parse(j.artifacts, nullptr, false))
      if (a.value("name", "") == name) entry = a;
    files = j.files;
    mesh_id = j.mesh_id;
  }
  if (entry.is_null()) throw std::out_of_range("job " + id + " has no artifact '" + name + "'");
  const fs::path dir = job_dir(files);
  const std::string kind = entry.value("kind", "");
  const std::string file = entry.value("file", "");
  std::string format = format_in;
  for (char& c : format) c = char(std::tolower(static_cast<unsigned char>(c)));
  ArtifactBytes out;
  out.content_type = "application/octet-stream";
  if (kind == "scalar_field") {
    if (format.empty()) format = "json";
    const std::string raw = read_file(dir / file);
    if (format == "f32") {
      out.bytes = raw;
    } else {
      ScalarField field;
      field.name = name;
      const json side = json::parse(read_file(dir / (name + ".field.json")), nullptr, false);
      if (side.is_object()) field.name = side.value("name", name);
      field.location = entry.value("location", "vertex") == "face" ? Location::face : Location::vertex;
      const std::string hint = entry.value("hint", "standard");
      field.hint = hint == "symmetric" ? ColorHint::symmetric : hint == "magnitude" ? ColorHint::magnitude
                   : hint == "categorical" ? ColorHint::categorical : ColorHint::standard;
      field.values.resize(raw.size() / sizeof(float));
      std::memcpy(field.values.data(), raw.data(), field.values.size() * sizeof(float));
      if (format == "json") {
        const auto [lo, hi] = field.range();
        json values = json::array();
        for (float v : field.values) values.push_back(v);
        out.bytes = json{{"name", field.name}, {"location", to_string(field.location)}, {"hint", to_string(field.hint)},
                         {"range", {lo, hi}}, {"values", values}}.dump();
        out.content_type = "application/json";
      } else if (format == "txt" || format == "csv" || format == "ply") {
        Mesh input;
        if (format == "ply") {
          const auto rec = meshes_.store().get_mesh(mesh_id);
          if (!rec) throw std::out_of_range("the mesh " + mesh_id + " of job " + id + " was deleted");
          input = *meshes_.mesh(*rec);
        }
        const fs::path tmp = dir / ("tmp-" + new_id() + "." + format);
        try {
          write_artifact(Artifact{name, field}, input, tmp);
          out.bytes = read_file(tmp);
        } catch (...) {
          std::error_code ec;
          fs::remove(tmp, ec);
          throw;
        }
        std::error_code ec;
        fs::remove(tmp, ec);
        if (format != "ply") out.content_type = format == "csv" ? "text/csv" : "text/plain; charset=utf-8";
      } else {
        throw UnsupportedFormat("a scalar field is served as txt, csv, ply, json or f32, not '" + format + "'");
      }
    }
  } else if (kind == "mesh") {
    if (format.empty() || format == "ply") {
      out.bytes = read_file(dir / file);
      format = "ply";
    } else {
      const MeshFormat f = format_from_name("x." + format);
      if (!can_write(f)) throw UnsupportedFormat("a mesh cannot be served as '" + format + "'");
      out.bytes = write_mesh_bytes(read_mesh_file(dir / file).mesh, f);
    }
  } else if (kind == "metrics") {
    if (!format.empty() && format != "json") throw UnsupportedFormat("metrics are served as json, not '" + format + "'");
    format = "json";
    out.bytes = read_file(dir / file);
    out.content_type = "application/json";
  } else if (kind == "voxel_grid") {
    const std::string ext = fs::path(file).extension().string().substr(1);
    if (format.empty()) format = ext;
    if (format == ext) {
      out.bytes = read_file(dir / file);
    } else {
      const VoxelGrid grid = read_voxel_grid(dir / file);
      if (format == "nrrd") out.bytes = encode_nrrd(grid);
      else if (format == "binvox") out.bytes = encode_binvox(grid);
      else if (format == "vti") out.bytes = encode_vti(grid);
      else if (format == "vox") out.bytes = encode_vox(grid);
      else throw UnsupportedFormat("a voxel grid is served as nrrd, binvox, vti or vox, not '" + format + "'");
    }
  } else if (kind == "skeleton") {
    // Stored as .obj; also served in the other skeleton files (io/skeleton_io.h).
    if (format.empty()) format = "obj";
    const std::string stored = read_file(dir / file);
    if (format == "obj") {
      out.bytes = stored;
    } else {
      if (format != "cg" && format != "json" && format != "polylines")
        throw UnsupportedFormat("a skeleton is served as obj, cg, json or polylines, not '" + format + "'");
      const SkeletonFormat f = skeleton_format_from_name("s." + std::string(format == "polylines" ? "polylines.txt" : format));
      out.bytes = write_skeleton_bytes(read_skeleton_bytes(stored, SkeletonFormat::obj, file), f);
      if (format == "polylines") format = "polylines.txt";
    }
    out.content_type = format == "json" ? "application/json" : "text/plain; charset=utf-8";
  } else {
    const std::string ext = fs::path(file).extension().string().substr(1);
    if (!format.empty() && format != ext) throw UnsupportedFormat("a " + kind + " is served as " + ext + ", not '" + format + "'");
    format = ext;
    out.bytes = read_file(dir / file);
  }
  out.file_name = name + "." + format;
  return out;
}

bool JobScheduler::launch(Job& j) {
  const fs::path dir = job_dir(j.id);
  std::error_code ec;
  fs::remove_all(dir, ec);
  fs::create_directories(dir, ec);
  json files = json::object();
  const json inputs = job_inputs(j.inputs, j.mesh_id);
  for (const auto& [name, in] : inputs.items()) {
    if (in.is_object()) {  // an earlier job's artifact
      try {
        files[name] = artifact_file_locked(in.value("job", ""), in.value("artifact", ""), "").string();
      } catch (const std::exception& e) {
        j.error = std::string("input '") + name + "': " + e.what();
        return false;
      }
      continue;
    }
    const auto rec = meshes_.store().get_mesh(in.get<std::string>());
    if (!rec) {
      j.error = "the mesh " + in.get<std::string>() + " (input '" + name + "') was deleted";
      return false;
    }
    files[name] = meshes_.store().blob_file(*rec).string();
  }
  try {
    write_file_bytes(dir / "job.json",
                     json{{"algorithm", j.algorithm}, {"params", json::parse(j.params)}, {"inputs", files}, {"out", dir.string()}}
                         .dump());
  } catch (const DiskFull&) {
    j.error = "the server's storage is full: the job could not start";
    return false;
  } catch (const IoError& e) {
    j.error = e.what();
    return false;
  }
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) {
    j.error = "pipe failed";
    return false;
  }
  ChildOptions child;
  child.memory_mb = config_.memory_mb;
  child.stdout_fd = fds[1];
  child.stderr_file = dir / "stderr.txt";
  const pid_t pid = spawn_child({config_.worker.string(), (dir / "job.json").string()}, child);
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    j.error = "fork failed";
    return false;
  }
  ::close(fds[1]);
  ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
  ++workers_started_;
  j.pid = pid;
  j.out_fd = fds[0];
  j.launched = Clock::now();
  j.state = "running";
  j.started = now_iso8601();
  j.stage = "starting";
  return true;
}

// Why a worker's artifact list does not match its files ("" when it does):
// each entry names a plain file of the job's directory that is there, a
// scalar field's file holds its count of floats, and only text may be empty.  A worker killed while
// writing, or a plugin's, must not make a job done without its results.
static std::string incomplete_artifact(const fs::path& dir, const json& artifacts) {
  if (!artifacts.is_array()) return "no artifact list";
  for (const auto& a : artifacts) {
    const std::string name = a.is_object() ? a.value("name", "") : "";
    const std::string file = a.is_object() ? a.value("file", "") : "";
    if (name.empty() || file.empty() || file.find('/') != std::string::npos || file == "." || file == "..")
      return "an artifact without a name or a file";
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(dir / file, ec);
    if (ec) return "artifact '" + name + "': its file is missing";
    if (a.value("kind", "") == "scalar_field") {
      const json count = a.value("count", json());
      if (!count.is_number_unsigned() || size != count.get<std::uintmax_t>() * sizeof(float))
        return "artifact '" + name + "': " + std::to_string(size) + " bytes for " + count.dump() + " values";
    } else if (size == 0 && a.value("kind", "") != "text") {  // an extracted message may be empty
      return "artifact '" + name + "': its file is empty";
    }
  }
  return "";
}

void JobScheduler::reap(Job& j, int status, std::vector<json>& events) {
  if (j.out_fd >= 0) ::close(j.out_fd);
  j.out_fd = -1;
  j.pid = -1;
  j.bytes = dir_bytes(job_dir(j.id));
  if (j.cancelled) {  // already cancelled (state, event): only its size is new
    save(j);
    return;
  }
  const fs::path dir = job_dir(j.id);
  std::string state = "failed";
  if (j.timed_out) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", config_.timeout_s);
    j.error = std::string("exceeded its time limit of ") + buf + " s";
  } else if (WIFEXITED(status) && WEXITSTATUS(status) == 0 && fs::exists(dir / "result.json")) {
    const json result = parse_json_or_discarded(read_file(dir / "result.json"));
    const std::string broken = result.is_object() ? incomplete_artifact(dir, result.value("artifacts", json())) : "";
    if (!broken.empty()) {
      j.error = "the worker's results are incomplete: " + broken;
    } else if (result.is_object()) {
      state = "done";
      j.artifacts = result.value("artifacts", json::array()).dump();
      j.files = j.id;
      cache_[j.cache_key] = j.id;
      j.progress = 1;
      j.stage = "done";
    } else {
      j.error = "the worker wrote an unreadable result";
    }
  } else {
    std::string text = trim(read_file(dir / "error.txt"));
    if (text.empty()) text = trim(read_file(dir / "stderr.txt"));
    const bool oom = (WIFEXITED(status) && WEXITSTATUS(status) == 3) || text.find("bad_alloc") != std::string::npos;
    if (oom && config_.memory_mb > 0) j.error = "exceeded its memory limit of " + std::to_string(config_.memory_mb) + " MB";
    else if (WIFEXITED(status) && WEXITSTATUS(status) == 4)
      j.error = "the server's storage is full: the job's results could not be written";
    else if (WIFSIGNALED(status)) j.error = "killed by signal " + signal_name(WTERMSIG(status));
    else if (WIFEXITED(status) && WEXITSTATUS(status) == 127 && text.empty()) j.error = "the worker could not be started";
    else j.error = text.empty() ? "the worker exited with status " + std::to_string(WEXITSTATUS(status)) : text;
  }
  j.state = state;
  j.finished = now_iso8601();
  save(j);
  events.push_back({{"type", state == "done" ? "job_done" : "job_failed"}, {"job", job_json(j)}});
}

void JobScheduler::loop() {
  std::vector<json> pending;  // events gathered under the lock, sent outside it
  for (;;) {
    std::vector<json> events = std::move(pending);
    pending.clear();
    std::vector<pollfd> fds;
    {
      std::unique_lock lock(mutex_);
      if (stopping_) break;
      for (const std::string& id : std::vector<std::string>(unsaved_.begin(), unsaved_.end()))
        if (const auto it = jobs_.find(id); it != jobs_.end()) save(*it->second);
      // Start queued jobs, round-robin over owners.
      while (int(running_ids_.size()) < config_.max_workers) {
        auto it = queues_.upper_bound(last_owner_);
        for (std::size_t k = 0; k <= queues_.size(); ++k) {
          if (it == queues_.end()) it = queues_.begin();
          if (it == queues_.end() || !it->second.empty()) break;
          ++it;
        }
        if (it == queues_.end() || it->second.empty()) break;
        last_owner_ = it->first;
        const std::string id = it->second.front();
        it->second.pop_front();
        Job& j = *jobs_.at(id);
        if (launch(j)) {
          running_ids_.push_back(id);
          j.last_event = Clock::now();
          save(j);
          events.push_back({{"type", "job_progress"}, {"job", {{"id", j.id}, {"state", j.state}, {"progress", 0.0}, {"stage", j.stage}}}});
        } else {
          j.state = "failed";
          j.finished = now_iso8601();
          j.bytes = dir_bytes(job_dir(j.id));
          save(j);
          events.push_back({{"type", "job_failed"}, {"job", job_json(j)}});
        }
      }
      // Limits, cancellation, exits.
      const auto now = Clock::now();
      for (std::size_t k = 0; k < running_ids_.size();) {
        Job& j = *jobs_.at(running_ids_[k]);
        if (!j.cancelled && !j.timed_out && config_.timeout_s > 0 &&
            now - j.launched > std::chrono::duration<double>(config_.timeout_s)) {
          j.timed_out = true;
          ::kill(j.pid, SIGKILL);
        }
        if (j.cancelled && now - j.term_sent > std::chrono::seconds(1)) ::kill(j.pid, SIGKILL);
        int status = 0;
        if (j.out_fd < 0 && ::waitpid(j.pid, &status, WNOHANG) == j.pid) {
          reap(j, status, events);
          running_ids_.erase(running_ids_.begin() + long(k));
          continue;
        }
        if (j.out_fd >= 0) fds.push_back({j.out_fd, POLLIN, 0});
        ++k;
      }
    }
    for (auto& e : events)
      if (on_event) on_event(e, job_access(e["job"].value("id", "")));
    events.clear();
    // Wait for output, an exit (EOF on the pipe) or a wake-up.
    fds.push_back({wake_pipe_[0], POLLIN, 0});
    bool any_closed_fd_waiting = false;
    {
      std::lock_guard lock(mutex_);
      for (const auto& id : running_ids_) any_closed_fd_waiting |= jobs_.at(id)->out_fd < 0;
    }
    ::poll(fds.data(), fds.size(), any_closed_fd_waiting ? 5 : 100);
    if (fds.back().revents) {
      char buf[256];
      while (::read(wake_pipe_[0], buf, sizeof buf) > 0) {
      }
    }
    std::lock_guard lock(mutex_);
    for (std::size_t k = 0; k + 1 < fds.size(); ++k) {
      if (!fds[k].revents) continue;
      Job* jp = nullptr;
      for (const auto& id : running_ids_)
        if (jobs_.at(id)->out_fd == fds[k].fd) jp = jobs_.at(id).get();
      if (!jp) continue;
      Job& j = *jp;
      char buf[4096];
      ssize_t n;
      bool eof = false;
      while ((n = ::read(j.out_fd, buf, sizeof buf)) > 0) j.out_buf.append(buf, std::size_t(n));
      if (n == 0) eof = true;
      bool updated = false;
      for (std::size_t nl; (nl = j.out_buf.find('\n')) != std::string::npos;) {
        const std::string line = j.out_buf.substr(0, nl);
        j.out_buf.erase(0, nl + 1);
        if (line.rfind("progress ", 0) == 0) {
          char* end = nullptr;
          const double f = std::strtod(line.c_str() + 9, &end);
          if (end != line.c_str() + 9) {
            j.progress = std::clamp(f, 0.0, 1.0);
            j.stage = *end == ' ' ? std::string(end + 1) : std::string();
            updated = true;
          }
        }
      }
      if (j.out_buf.size() > 65536) j.out_buf.clear();
      if (updated && !j.cancelled && Clock::now() - j.last_event >= std::chrono::milliseconds(100)) {
        j.last_event = Clock::now();
        events.push_back({{"type", "job_progress"}, {"job", {{"id", j.id}, {"state", j.state}, {"progress", j.progress}, {"stage", j.stage}}}});
      }
      if (eof) {
        ::close(j.out_fd);
        j.out_fd = -1;
      }
    }
    pending = std::move(events);  // sent at the top of the next turn, outside the lock
  }
  // Stopping: kill the workers; their jobs stay "running" and run again at the next start.
  std::lock_guard lock(mutex_);
  for (const auto& id : running_ids_) {
    Job& j = *jobs_.at(id);
    if (j.pid > 0) {
      ::kill(j.pid, SIGKILL);
      ::waitpid(j.pid, nullptr, 0);
    }
    if (j.out_fd >= 0) ::close(j.out_fd);
  }
}

}  // namespace cgview::server
