// Admission: whether a job request may run, and the job it becomes.  It
// knows the algorithms the worker runs (from `cgview-worker --list`),
// checks the request's algorithm, its inputs (each one the caller may
// read: a stored mesh, or an earlier job's artifact) and its parameters
// (ranges, selections, the algorithm's own precheck against the inputs'
// stored reports), fills in the defaults, and keys the job for the result
// cache.  Quotas and the cache itself are the scheduler's, which holds the
// jobs they count.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "artifacts/artifact_codec.h"
#include "jobs/job.h"
#include "mesh_service.h"

namespace cgview::server {

// What admission asks of the jobs already there.
class JobLookup {
 public:
  virtual ~JobLookup() = default;
  // The file of a done job's artifact of that kind ("": any) that the
  // caller may read; throws std::out_of_range or InvalidInput.
  virtual std::filesystem::path artifact_file(const std::string& job, const std::string& artifact,
                                              const std::string& kind, const Caller& caller) const = 0;
  virtual ExportedArtifact artifact(const std::string& job, const std::string& artifact, const std::string& format,
                                    const Caller& caller) = 0;
  // Throws QuotaExceeded when the caller may not add `bytes` (`what`) or
  // start another job.
  virtual void check_storage(const Caller& caller, std::uint64_t bytes, const std::string& what) const = 0;
  virtual void check_job_count(const Caller& caller) const = 0;
};

// A plugin's algorithm as the plugin service finds it for a caller.
struct PluginAlgorithm {
  nlohmann::json description;  // as GET /api/v1/algorithms lists an algorithm
  std::string plugin_id, library, library_sha;
};
// Throws std::out_of_range (no such plugin or algorithm for this caller),
// Forbidden (plugins are off for them) or InvalidInput (not built).
using PluginResolver =
    std::function<PluginAlgorithm(const std::string& plugin, const std::string& algorithm, const Caller& caller)>;

class Admission {
 public:
  // Asks `worker` (cgview-worker) what it runs; when it cannot say, the
  // algorithms linked into the server stand in (and jobs fail with the reason).
  Admission(MeshService& meshes, const std::filesystem::path& worker);

  // GET /api/v1/algorithms: the algorithms a client may run (test ones hidden).
  nlohmann::json algorithms_json() const;

  // The job a request makes, not yet stored or queued (no id, seq or
  // state yet).  Throws std::out_of_range (an unknown algorithm, or an input
  // the caller cannot read) or InvalidInput (naming the input or parameter
  // and the rule broken).  An input that names an earlier job's output mesh
  // stores that mesh (its id appended to `new_meshes`).
  // A request with "plugin": ID runs that plugin's algorithm, resolved here.
  // `system`: the server's own request, which may name a hidden system
  // algorithm (plugin_build); a client's never does.
  Job admit(const nlohmann::json& request, const Caller& caller, JobLookup& jobs, std::vector<std::string>* new_meshes,
            bool system = false) const;
  void set_plugin_resolver(PluginResolver r) { plugins_ = std::move(r); }

 private:
  MeshService& meshes_;
  std::map<std::string, nlohmann::json> algorithms_;  // by name, as the worker lists them
  PluginResolver plugins_;
};

}  // namespace cgview::server
