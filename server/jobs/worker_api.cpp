// The worker's side of a job on a node without the data directory: its
// job.json, its inputs, its results and its progress, each behind the job's
// own token (scheduler.h).
#include <fstream>

#include "auth.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "jobs/scheduler.h"

namespace cgview::server {

namespace fs = std::filesystem;

const Job& JobScheduler::worker_job_locked(const std::string& id, std::string_view token) const {
  const auto it = jobs_.find(id);
  if (it == jobs_.end() || !it->second->in_flight || !active(it->second->state) ||
      !same_digest(sha256_hex(token), it->second->worker_token_sha))
    throw WorkerTokenRefused("not a token of a running job " + id);
  return *it->second;
}

std::string JobScheduler::worker_spec(const std::string& id, std::string_view token) const {
  fs::path file;
  {
    std::lock_guard lock(mutex_);
    file = run_dir(worker_job_locked(id, token).id) / "job.json";
  }
  return read_file_bytes(file, 1 << 20);
}

fs::path JobScheduler::worker_input(const std::string& id, std::string_view token, const std::string& name) const {
  std::lock_guard lock(mutex_);
  const Job& j = worker_job_locked(id, token);
  std::string error;
  const auto files = input_files(j, &error);
  if (!files) throw std::out_of_range(error);
  if (!files->contains(name)) throw std::out_of_range("job " + id + " has no input '" + name + "'");
  return (*files)[name].get<std::string>();
}

void JobScheduler::worker_put(const std::string& id, std::string_view token, const std::string& file,
                              const std::string& bytes) {
  fs::path dir;
  {
    std::lock_guard lock(mutex_);
    dir = run_dir(worker_job_locked(id, token).id);  // the token first: nothing is said to another caller
  }
  const bool plain =
      !file.empty() && file.size() <= 128 && file[0] != '.' &&
      file.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789._-") == std::string::npos;
  if (!plain || file == "job.json" || file == "slurm-job.sh")
    throw InvalidInput("'" + file + "' is not a result file name: letters, digits, '.', '_', '-'");
  // Its exit status and stderr are the run's (where a shared directory's
  // batch script and Slurm leave them); its results are the job's own.
  // (Named as a shared directory's run 0 names them: slurm_executor.cpp.)
  if (file == "worker.exit") write_file_bytes(dir / "worker.exit.0", bytes);
  else if (file == "stderr.txt") write_file_bytes(dir / file, bytes);
  else write_file_bytes(dir / "work" / file, bytes);
}

void JobScheduler::worker_progress(const std::string& id, std::string_view token, const std::string& line) {
  std::lock_guard lock(mutex_);
  const Job& j = worker_job_locked(id, token);  // the token first: nothing is said to another caller
  if (line.size() > 4096 || line.rfind("progress ", 0) != 0 || line.find('\n') != std::string::npos)
    throw InvalidInput("a progress line is \"progress FRACTION STAGE\" (one line)");
  // Appended to its output, where the executor reads progress as it does a shared directory's.
  std::ofstream f(run_dir(j.id) / "stdout.0", std::ios::binary | std::ios::app);
  f << line << '\n';
}

}  // namespace cgview::server
