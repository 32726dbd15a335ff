// Users' plugins on the server: an algorithm file a user saves, builds and
// runs from the viewer's code panel or the API (algorithms/plugins/plugin.h
// says what a plugin is).  A plugin belongs to its owner, is read by those
// it is shared with, and its algorithms are known to them alone, so two
// users' "height" never meet.  The admin's plugin directory (--plugin-dir)
// gives every user the lab's plugins, rebuilt when a file there changes.
//
// A build is a job (the worker's plugin_build, in the sandbox, under the
// owner's job limits, with progress and cancel, cached by the file's
// content); its library is kept under DATA/plugins/ by its SHA-256, and a
// job of the plugin's algorithm names the library it was submitted with.
// The server never loads a user's code itself: it checks a job's
// parameters against the description the build wrote.
#pragma once

#include <atomic>
#include <condition_variable>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <thread>

#include "jobs/admission.h"
#include "store.h"

struct sqlite3;

namespace cgview::server {

class JobScheduler;

struct PluginConfig {
  // Whether users' code may run here: false where the sandbox cannot start
  // (sandbox.h), unless the admin allows it knowingly.  The local user of a
  // loopback server runs their own code on their own machine either way.
  bool sandboxed = false;
  bool allow_without_sandbox = false;
  std::filesystem::path admin_dir;  // the lab's plugins (*.cpp); empty: none
  double scan_s = 2;                // how often admin_dir is looked at
  // Per user (limits.plugins and users.NAME.plugins): may they build and run plugins.
  std::function<bool(const Caller&)> allowed;
};

// 403: plugins are off for this caller, with the reason.
struct PluginsOff : Forbidden {
  using Forbidden::Forbidden;
};

class PluginService {
 public:
  PluginService(Store& store, JobScheduler& jobs, PluginConfig config);
  ~PluginService();
  PluginService(const PluginService&) = delete;
  PluginService& operator=(const PluginService&) = delete;

  // The plugins the caller reads (their own, those shared with them, the
  // lab's), without their source; one with it.  An unknown id, or another
  // user's not shared, throws std::out_of_range.
  // A build whose job has ended is settled first: a client that saw the
  // job end reads the build's outcome, not "building".
  nlohmann::json list(const Caller& caller);
  nlohmann::json get(const std::string& id, const Caller& caller);
  // Saves a new plugin (name: a plain name, source: C++ text); changes one
  // of the caller's own ({"name"}, {"source"} or both: a new source is built
  // again); deletes one.  Throws InvalidInput, PluginsOff, Forbidden.
  nlohmann::json create(const nlohmann::json& body, const Caller& caller);
  nlohmann::json update(const std::string& id, const nlohmann::json& body, const Caller& caller);
  void remove(const std::string& id, const Caller& caller);
  // Starts a build of the plugin's current source: the build job's JSON.
  nlohmann::json build(const std::string& id, const Caller& caller);
  // Who reads the plugin (for sharing); throws std::out_of_range.
  Access access(const std::string& id, const Caller& caller) const;
  // The algorithms of the plugins the caller reads and may run, as GET
  // /api/v1/algorithms lists them, each with "plugin": its plugin's id.
  nlohmann::json algorithms_json(const Caller& caller) const;
  // For admission: a plugin's algorithm and its library.
  PluginAlgorithm resolve(const std::string& id, const std::string& algorithm, const Caller& caller) const;
  // A job's event (the scheduler's on_event): a build that ended updates its plugin.
  void on_job_event(const nlohmann::json& event);
  // Whether the caller may build and run plugins, and if not, why.
  std::optional<std::string> refused(const Caller& caller) const;
  // Looks at the admin's directory now (the scanning thread does it every scan_s).
  void scan_admin_dir();
  // Stops the scanning thread (before the scheduler goes).
  void stop();

 private:
  struct Plugin {
    std::string id, owner, name, source, created, updated, origin = "user";
    std::string build_job, state = "none";  // none, building, ok, failed
    std::string library, library_sha, error;
    nlohmann::json algorithms = nlohmann::json::array(), diagnostics = nlohmann::json::array();
  };
  nlohmann::json to_json(const Plugin& p, bool with_source) const;
  const Plugin& readable(const std::string& id, const Caller& caller) const;  // under mutex_
  Plugin& owned(const std::string& id, const Caller& caller);                 // under mutex_
  Access access_locked(const Plugin& p) const;
  // Whether the caller's lists (plugins, algorithms) show it (under mutex_).
  bool listed(const Plugin& p, const Caller& caller) const;
  void save(const Plugin& p);
  // Reads an ended build job's results into its plugin (under mutex_).
  void settle_builds_locked();
  void finish_build(Plugin& p, const nlohmann::json& job);
  nlohmann::json start_build(Plugin& p, const Caller& caller);  // under mutex_

  Store& store_;
  JobScheduler& jobs_;
  PluginConfig config_;
  std::filesystem::path library_dir_;
  sqlite3* db_ = nullptr;
  mutable std::mutex mutex_;
  std::map<std::string, Plugin> plugins_;
  std::map<std::string, std::filesystem::file_time_type> admin_seen_;  // file -> its time when last built
  std::atomic<bool> stopping_{false};
  std::mutex scan_mutex_;
  std::condition_variable scan_cv_;
  std::thread scanner_;
};

}  // namespace cgview::server
