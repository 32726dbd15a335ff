#include "plugin_service.h"

#include <sqlite3.h>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "jobs/scheduler.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kLab = "lab";  // the owner of the admin directory's plugins: every user reads them
constexpr std::size_t kMaxSource = 512 * 1024;

std::string checked_name(const json& v) {
  if (!v.is_string()) throw InvalidInput("\"name\" must be a string, such as \"height\"");
  const std::string n = v.get<std::string>();
  if (n.empty() || n.size() > 64 ||
      n.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
    throw InvalidInput("\"name\": 1 to 64 letters, digits, '_' or '-', got \"" + n.substr(0, 80) + "\"");
  return n;
}

std::string checked_source(const json& v) {
  if (!v.is_string()) throw InvalidInput("\"source\" must be the file's C++ text");
  if (v.get_ref<const std::string&>().size() > kMaxSource)
    throw InvalidInput("\"source\" is over " + std::to_string(kMaxSource / 1024) + " KB");
  return v.get<std::string>();
}

}  // namespace

PluginService::PluginService(Store& store, JobScheduler& jobs, PluginConfig config)
    : store_(store), jobs_(jobs), config_(std::move(config)), library_dir_(store.data_dir() / "plugins") {
  std::error_code ec;
  fs::create_directories(library_dir_, ec);
  db_ = open_database(store.data_dir() / "cgview.db");
  exec_sql(db_, "CREATE TABLE IF NOT EXISTS plugins (id TEXT PRIMARY KEY, record TEXT NOT NULL);", "plugins");
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db_, "SELECT record FROM plugins", -1, &s, nullptr);
  while (s && sqlite3_step(s) == SQLITE_ROW) {
    const json r = parse_json_or_discarded(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
    if (!r.is_object()) continue;
    Plugin p;
    p.id = r.value("id", ""), p.owner = r.value("owner", ""), p.name = r.value("name", "");
    p.source = r.value("source", ""), p.created = r.value("created", ""), p.updated = r.value("updated", "");
    p.origin = r.value("origin", "user"), p.build_job = r.value("build_job", ""), p.state = r.value("state", "none");
    p.library = r.value("library", ""), p.library_sha = r.value("library_sha", ""), p.error = r.value("error", "");
    p.algorithms = r.value("algorithms", json::array()), p.diagnostics = r.value("diagnostics", json::array());
    // A build the server stopped under: its job ends again after the restart, or is built anew.
    if (p.state == "building") p.state = "none";
    plugins_[p.id] = std::move(p);
  }
  sqlite3_finalize(s);
  if (!config_.admin_dir.empty()) {
    scanner_ = std::thread([this] {
      while (!stopping_) {
        scan_admin_dir();
        std::unique_lock lock(scan_mutex_);
        scan_cv_.wait_for(lock, std::chrono::duration<double>(config_.scan_s), [this] { return stopping_.load(); });
      }
    });
  }
}

void PluginService::stop() {
  stopping_ = true;
  scan_cv_.notify_all();
  if (scanner_.joinable()) scanner_.join();
}

PluginService::~PluginService() {
  stop();
  sqlite3_close(db_);
}

void PluginService::save(const Plugin& p) {
  const json r = {{"id", p.id},
                  {"owner", p.owner},
                  {"name", p.name},
                  {"source", p.source},
                  {"created", p.created},
                  {"updated", p.updated},
                  {"origin", p.origin},
                  {"build_job", p.build_job},
                  {"state", p.state},
                  {"library", p.library},
                  {"library_sha", p.library_sha},
                  {"error", p.error},
                  {"algorithms", p.algorithms},
                  {"diagnostics", p.diagnostics}};
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db_, "INSERT OR REPLACE INTO plugins (id, record) VALUES (?1, ?2)", -1, &s, nullptr);
  const std::string text = r.dump();
  sqlite3_bind_text(s, 1, p.id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(s, 2, text.data(), int(text.size()), SQLITE_TRANSIENT);
  const int rc = sqlite3_step(s);
  sqlite3_finalize(s);
  if (rc == SQLITE_FULL) throw DiskFull("plugins: the server's storage is full");
  if (rc != SQLITE_DONE) throw IoError(std::string("plugins: ") + sqlite3_errmsg(db_));
}

Access PluginService::access_locked(const Plugin& p) const {
  if (p.origin == "lab") {
    Access a{kLab};
    a.everyone = true;
    return a;
  }
  return store_.access("plugin", p.id, p.owner);
}

Access PluginService::access(const std::string& id, const Caller& caller) const {
  std::lock_guard lock(mutex_);
  return access_locked(readable(id, caller));
}

bool PluginService::listed(const Plugin& p, const Caller& caller) const {
  // A submission's copy (teaching/grading.h) is read by id, not listed: an
  // admin's menus would otherwise hold every student's every submission.
  if (p.owner.starts_with("grading:") && caller.user != p.owner) return false;
  return access_locked(p).allows(caller);
}

const PluginService::Plugin& PluginService::readable(const std::string& id, const Caller& caller) const {
  const auto it = plugins_.find(id);
  if (it == plugins_.end() || !access_locked(it->second).allows(caller))
    throw std::out_of_range("no plugin with id '" + id + "'");
  return it->second;
}

PluginService::Plugin& PluginService::owned(const std::string& id, const Caller& caller) {
  const Plugin& p = readable(id, caller);
  if (p.origin == "lab")
    throw Forbidden("plugin " + id + " is the lab's: it changes with its file in the plugin directory");
  if (!access_locked(p).owned_by(caller))
    throw Forbidden("plugin " + id + " is " + p.owner + "'s: only its owner changes it");
  return plugins_.at(id);
}

std::optional<std::string> PluginService::refused(const Caller& caller) const {
  if (config_.allowed && !config_.allowed(caller))
    return "plugins are off for user '" + caller.user + "' (limits.plugins)";
  if (!config_.sandboxed && !config_.allow_without_sandbox && caller.user != "local" && caller.user != kLab)
    return "plugins are off: this server cannot sandbox them (see its start message)";
  return std::nullopt;
}

json PluginService::to_json(const Plugin& p, bool with_source) const {
  json algos = json::array();
  for (const auto& a : p.algorithms) algos.push_back(a.value("name", ""));
  json out = {{"id", p.id},
              {"name", p.name},
              {"owner", p.owner},
              {"origin", p.origin},
              {"created", p.created},
              {"updated", p.updated},
              {"source_bytes", p.source.size()},
              {"build",
               {{"state", p.state},
                {"job", p.build_job.empty() ? json(nullptr) : json(p.build_job)},
                {"error", p.error.empty() ? json(nullptr) : json(p.error)},
                {"diagnostics", p.diagnostics},
                {"algorithms", algos}}}};
  if (with_source) out["source"] = p.source;
  return out;
}

json PluginService::list(const Caller& caller) {
  std::lock_guard lock(mutex_);
  settle_builds_locked();
  json out = json::array();
  for (const auto& [id, p] : plugins_)
    if (listed(p, caller)) out.push_back(to_json(p, false));
  return {{"plugins", out}};
}

json PluginService::get(const std::string& id, const Caller& caller) {
  std::lock_guard lock(mutex_);
  settle_builds_locked();
  return to_json(readable(id, caller), true);
}

void PluginService::settle_builds_locked() {
  for (auto& [id, p] : plugins_) {
    if (p.state != "building") continue;
    const auto job = jobs_.get(p.build_job);
    const std::string state = job ? job->value("state", "") : "";
    if (state == "queued" || state == "running") continue;
    try {
      if (job) finish_build(p, *job);
      else p.state = "none";  // the job is gone
    } catch (const std::exception& e) {
      p.state = "failed";
      p.error = e.what();
    }
  }
}

json PluginService::create(const json& body, const Caller& caller) {
  if (const auto why = refused(caller)) throw PluginsOff(*why);
  if (!body.is_object()) throw InvalidInput("the body is {\"name\": NAME, \"source\": C++ TEXT}");
  Plugin p;
  p.name = checked_name(body.value("name", json()));
  p.source = checked_source(body.value("source", json()));
  p.id = "p" + new_id();
  p.owner = caller.user;
  p.created = p.updated = now_iso8601();
  std::lock_guard lock(mutex_);
  save(p);
  plugins_[p.id] = p;
  return to_json(p, true);
}

json PluginService::update(const std::string& id, const json& body, const Caller& caller) {
  std::lock_guard lock(mutex_);
  Plugin p = owned(id, caller);  // another user's answers as unknown, before the body is looked at
  if (!body.is_object() || (!body.contains("name") && !body.contains("source")))
    throw InvalidInput("the body is {\"name\": NAME} and/or {\"source\": C++ TEXT}");
  if (body.contains("name")) p.name = checked_name(body["name"]);
  if (body.contains("source")) {
    const std::string s = checked_source(body["source"]);
    if (s != p.source) {
      if (const auto why = refused(caller)) throw PluginsOff(*why);
      p.source = s;
      // What was built is of the old text: the plugin's algorithms stay
      // runnable until a new build replaces them, but the state says so.
      if (p.state != "building") p.state = p.state == "ok" ? "changed" : "none";
    }
  }
  p.updated = now_iso8601();
  save(p);
  plugins_[id] = p;
  return to_json(p, true);
}

void PluginService::remove(const std::string& id, const Caller& caller) {
  std::lock_guard lock(mutex_);
  owned(id, caller);
  sqlite3_stmt* s = nullptr;
  sqlite3_prepare_v2(db_, "DELETE FROM plugins WHERE id = ?1", -1, &s, nullptr);
  sqlite3_bind_text(s, 1, id.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_step(s);
  sqlite3_finalize(s);
  plugins_.erase(id);
  // Its library stays while a queued job may name it; libraries are shared by content.
}

json PluginService::build(const std::string& id, const Caller& caller) {
  json request;
  {
    std::lock_guard lock(mutex_);
    const Plugin& p = readable(id, caller);
    if (const auto why = refused(caller)) throw PluginsOff(*why);
    if (p.origin != "lab" || caller.user != kLab) owned(id, caller);
    request = {{"algorithm", "plugin_build"},
               {"inputs", json::object()},
               {"params", {{"source", p.source}, {"file", p.name + ".cpp"}}}};
  }
  // Submitted without the lock: a cached build ends at once, and its event comes back here.
  const json job = jobs_.submit(request, caller, nullptr, true);
  std::lock_guard lock(mutex_);
  const auto it = plugins_.find(id);
  if (it == plugins_.end()) return job;
  Plugin& p = it->second;
  p.build_job = job.value("id", "");
  p.state = "building";
  p.error.clear();
  if (job.value("state", "") != "queued" && job.value("state", "") != "running") finish_build(p, job);
  else save(p);
  return job;
}

void PluginService::finish_build(Plugin& p, const json& job) {
  const std::string state = job.value("state", "");
  const std::string id = job.value("id", "");
  const Caller reader = Caller::local();
  auto text = [&](const char* name) -> std::optional<std::string> {
    try {
      return jobs_.artifact(id, name, "txt", reader).bytes;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  };
  p.diagnostics = json::array();
  if (state != "done") {
    p.state = "failed";
    const json error = job.value("error", json());
    p.error =
        error.is_string() && !error.get<std::string>().empty() ? error.get<std::string>() : "the build was " + state;
    save(p);
    return;
  }
  if (const auto d = text("diagnostics")) p.diagnostics = parse_json_or_discarded(*d);
  if (!p.diagnostics.is_array()) p.diagnostics = json::array();
  const auto library = text("library");
  const auto algorithms = text("algorithms");
  if (!library || !algorithms) {
    p.state = "failed";
    const json w = job.value("warnings", json::array());
    p.error = !w.empty() && w[0].is_string() ? w[0].get<std::string>() : "the file does not build";
    save(p);
    return;
  }
  const std::string sha = sha256_hex(*library);
  const fs::path file = library_dir_ / (sha + ".so");
  std::error_code ec;
  if (!fs::exists(file, ec)) {
    write_file_bytes(fs::path(file.string() + ".tmp"), *library);
    fs::rename(file.string() + ".tmp", file, ec);
  }
  json algos = parse_json_or_discarded(*algorithms);
  if (!algos.is_array()) algos = json::array();
  for (auto& a : algos) a["plugin"] = p.id;
  p.algorithms = algos;
  p.library = file.string();
  p.library_sha = sha;
  p.state = "ok";
  p.error.clear();
  save(p);
}

void PluginService::on_job_event(const json& event) {
  const std::string type = event.value("type", "");
  if (type != "job_done" && type != "job_failed" && type != "job_cancelled") return;
  const json job = event.value("job", json::object());
  if (job.value("algorithm", "") != "plugin_build") return;
  std::lock_guard lock(mutex_);
  for (auto& [id, p] : plugins_)
    if (p.build_job == job.value("id", "") && p.state == "building") {
      try {
        finish_build(p, job);
      } catch (const std::exception& e) {
        p.state = "failed";
        p.error = e.what();
      }
    }
}

json PluginService::algorithms_json(const Caller& caller) const {
  json out = json::array();
  if (refused(caller)) return out;
  std::lock_guard lock(mutex_);
  for (const auto& [id, p] : plugins_)
    if (!p.library.empty() && listed(p, caller))
      for (const auto& a : p.algorithms) out.push_back(a);
  return out;
}

PluginAlgorithm PluginService::resolve(const std::string& id, const std::string& algorithm,
                                       const Caller& caller) const {
  if (const auto why = refused(caller)) throw PluginsOff(*why);
  std::lock_guard lock(mutex_);
  const Plugin& p = readable(id, caller);
  if (p.library.empty())
    throw InvalidInput("plugin " + id + " is not built" + (p.state == "failed" ? ": " + p.error : std::string()));
  for (const auto& a : p.algorithms)
    if (a.value("name", "") == algorithm) return {a, p.id, p.library, p.library_sha};
  std::string names;
  for (const auto& a : p.algorithms) names += (names.empty() ? "" : ", ") + a.value("name", std::string());
  throw std::out_of_range("plugin " + id + " has no algorithm '" + algorithm + "' (it has: " + names + ")");
}

void PluginService::scan_admin_dir() {
  std::error_code ec;
  std::vector<std::pair<fs::path, fs::file_time_type>> changed;
  for (const auto& e : fs::directory_iterator(config_.admin_dir, ec)) {
    if (e.path().extension() != ".cpp" || !e.is_regular_file(ec)) continue;
    const auto t = fs::last_write_time(e.path(), ec);
    std::lock_guard lock(mutex_);
    const auto seen = admin_seen_.find(e.path().string());
    if (seen == admin_seen_.end() || seen->second != t) changed.emplace_back(e.path(), t);
  }
  const Caller lab{kLab, true};
  for (const auto& [path, t] : changed) {
    std::string source;
    try {
      source = read_file_bytes(path, kMaxSource);
    } catch (const std::exception&) {
      continue;  // half-written or gone: the next look sees it
    }
    std::string stem = path.stem().string();
    for (char& c : stem)
      if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') c = '_';
    const std::string id = "lab-" + stem;
    {
      std::lock_guard lock(mutex_);
      admin_seen_[path.string()] = t;
      Plugin& p = plugins_[id];
      if (p.id.empty()) {
        p.id = id, p.owner = kLab, p.origin = "lab", p.name = stem, p.created = now_iso8601();
      } else if (p.source == source && p.state == "ok") {
        continue;  // touched, not changed
      }
      p.source = source;
      p.updated = now_iso8601();
      save(p);
    }
    try {
      build(id, lab);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cgview-server: the lab plugin %s: %s\n", path.c_str(), e.what());
    }
  }
}

}  // namespace cgview::server
