// The settings of the Slurm executor (the config file's "slurm" section).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cgview::server {

struct SlurmConfig {
  std::string partition, account, qos;   // sbatch's -p, -A, --qos ("": the cluster's default)
  std::vector<std::string> sbatch_args;  // more of sbatch's arguments, as they are
  int max_jobs = 200;                    // CGView jobs in the cluster at once (pending or running)
  // CGView jobs pending in the cluster at once: the rest wait in CGView's
  // fair queue, where owners take turns.  Slurm sees one user (the
  // server's), so jobs handed to it early would run in submission order,
  // one student's hundred before another's first.
  int max_pending = 16;
  double poll_s = 1;  // seconds between squeue calls
  // The nodes see the data directory at the same path (NFS): workers read
  // their inputs and write their results there.  Otherwise each worker
  // fetches its inputs from the server and sends its results back.
  bool shared_data = true;
  std::string server_url;  // how a node reaches the server (when not shared), e.g. http://head:8080
  // A job Slurm no longer knows (purged, lost with its node): queued again
  // (true) or failed with that reason.
  bool requeue_lost = false;
  std::filesystem::path worker;  // cgview-worker on the nodes ("": the server's own path)
  // With a shared data directory, workers start in the server's sandbox
  // (sandbox.h) on the nodes too, which then need bubblewrap (and setpriv
  // where the server runs as root); false runs them as plain processes.
  bool sandbox = true;
};

}  // namespace cgview::server
