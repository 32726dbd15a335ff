// Uploaded data as a done job's artifact (JobScheduler::import_data).
#include "jobs/job_files.h"
#include "jobs/scheduler.h"
#include "jobs/worker_result.h"
#include "core/errors.h"
#include "io/mesh_io.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

json JobScheduler::import_data(const std::string& file_name, const json& inputs, const DataReader& read,
                               const Caller& caller) {
  check_job_count(caller);
  auto j = std::make_shared<Job>();
  j->id = new_id();
  j->owner = caller.user;
  j->algorithm = "import";
  j->params = {{"file", file_name}};
  j->inputs = inputs.is_object() ? inputs : json::object();
  if (j->inputs.contains("mesh") && j->inputs["mesh"].is_string()) {
    j->mesh_id = j->inputs["mesh"].get<std::string>();
    if (const auto rec = meshes_.store().get_mesh(j->mesh_id)) j->mesh_sha = rec->sha256;
  }
  const fs::path dir = job_dir(j->id);
  try {
    fs::create_directories(dir);
    auto [entry, warnings] = read(dir);
    // Its name is the reader's (a child's, as untrusted as the file): a plain word, since files are named after it.
    const std::string name = entry.is_object() ? entry.value("name", "") : "";
    if (name.empty() || name.size() > 64 ||
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") != std::string::npos)
      throw InvalidInput(file_name + ": the reader named its artifact '" + name.substr(0, 64) + "'");
    const json artifacts = json::array({entry});
    // The same check as a worker's results get: a plain file of its size, whole.
    if (const std::string broken = incomplete_artifact(JobDir(dir), artifacts); !broken.empty())
      throw InvalidInput(file_name + ": " + broken);
    j->artifacts = artifacts;
    for (const std::string& w : warnings) j->warnings.push_back(w);
    write_file_bytes(dir / "result.json", json{{"artifacts", j->artifacts}, {"warnings", j->warnings}}.dump());
  } catch (...) {
    std::error_code ec;
    fs::remove_all(dir, ec);
    throw;
  }
  j->state = JobState::done;
  j->progress = 1;
  j->stage = "done";
  j->created = j->started = j->finished = now_iso8601();
  j->files = j->id;
  j->bytes = dir_bytes(dir);
  json out;
  {
    std::lock_guard lock(mutex_);
    j->seq = ++seq_;
    store_.put(*j);
    jobs_[j->id] = j;
    order_.push_back(j->id);
    out = job_json(*j);
  }
  if (on_event) on_event({{"type", "job_done"}, {"job", out}}, Access{j->owner});
  return out;
}

}  // namespace cgview::server
