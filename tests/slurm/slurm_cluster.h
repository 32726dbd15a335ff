// A real Slurm cluster on this machine for the tests: a private munged, one
// slurmctld and N slurmd (n1..nN, one host, a port each), all in one temporary
// directory, on random free ports, started and stopped by pid.  See README.md.
//
//   cgview::test::SlurmCluster cluster;
//   std::string why;
//   if (!SlurmCluster::available(&why)) GTEST_SKIP() << why;
//   ASSERT_TRUE(cluster.start(temp_dir("slurm"), 3, &why)) << why;
//   std::string id = cluster.submit("-w n2 --wrap 'hostname'", &why);
//   EXPECT_EQ(cluster.wait_ended(id), "COMPLETED");
//   cluster.stop();  // also in the destructor
//
// The daemons die with the thread that called start() (PR_SET_PDEATHSIG), so
// a crashed test leaves no controller behind; call start() from the thread
// that lives as long as the cluster (the test's own).
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace cgview::test {

class SlurmCluster {
 public:
  SlurmCluster() = default;
  ~SlurmCluster();
  SlurmCluster(const SlurmCluster&) = delete;
  SlurmCluster& operator=(const SlurmCluster&) = delete;

  // Whether munged, slurmctld, slurmd and the client commands are installed
  // (Debian: munge, slurm-wlm; ./setup.sh installs them); if not, why.
  static bool available(std::string* why = nullptr);

  // Replaces (or adds) one `Key=Value` line of slurm.conf before start():
  // set_conf("MinJobAge", "2"), set_conf("SlurmdTimeout", "5").  The defaults
  // are listed in slurm_cluster.cpp.
  void set_conf(const std::string& key, const std::string& value);

  // Writes slurm.conf and a munge key into dir (created if missing; the state
  // and spool of an earlier cluster there are removed), starts
  // munged, slurmctld and `nodes` slurmd, and waits (20 s at most) until sinfo
  // shows every node idle.  False, with the reason and the tail of the daemons'
  // logs in *why, if any of that fails; what was started is stopped again.
  bool start(const std::filesystem::path& dir, int nodes = 3, std::string* why = nullptr);

  // Cancels the jobs still queued or running (2 s at most), then SIGTERM and,
  // after 5 s, SIGKILL to each daemon it started, reaping each by pid.  Then
  // what jobs left behind (a slurmstepd outlives its slurmd by design) is
  // SIGKILLed: processes holding one of this cluster's daemon logs open
  // (slurmstepd), processes whose environment has this cluster's SLURM_CONF,
  // SLURM_CLUSTER_NAME and a SLURM_JOB_ID (a job's, even without its
  // slurmstepd), and the other processes of their sessions.  Never by name.
  void stop();

  bool running() const { return ctld_.pid > 0; }
  const std::filesystem::path& dir() const { return dir_; }
  std::filesystem::path conf() const { return dir_ / "slurm.conf"; }
  // "SLURM_CONF=/dir/slurm.conf ": a prefix for one simple shell command.
  std::string env() const;
  int nodes() const { return static_cast<int>(slurmd_.size()); }
  std::string node_name(int i) const { return std::string("n").append(std::to_string(i)); }
  int ctld_port() const { return ctld_port_; }

  pid_t munged_pid() const { return munged_.pid; }
  pid_t ctld_pid() const { return ctld_.pid; }
  // i is 1-based, as in the node's name; 0 if it is not running.
  pid_t slurmd_pid(int i) const;
  // Every pid this object has started (daemons, restarted ones included),
  // for a test that checks they are gone after stop().
  std::vector<pid_t> started_pids() const { return started_; }
  // The leftovers stop() had to SIGKILL (slurmstepd, jobs' processes).
  std::vector<pid_t> swept_pids() const { return swept_; }

  // SIGKILLs node i's slurmd and reaps it; its running jobs (their slurmstepd)
  // go on, as on a real node whose slurmd crashed.
  void kill_node(int i);
  // Starts node i's slurmd again (killing it first if it runs) and waits until
  // the controller has its new registration and the node responds.
  bool restart_node(int i, std::string* why = nullptr);

  // Runs a shell command with SLURM_CONF exported; stdout and stderr together.
  std::string run(const std::string& cmd, int* rc = nullptr) const;

  // `sbatch --parsable ARGS`: the job id, or "" with the output in *why.
  std::string submit(const std::string& sbatch_args, std::string* why = nullptr) const;
  // The job's state from `squeue -t all` (PENDING, RUNNING, COMPLETED,
  // FAILED, CANCELLED, TIMEOUT, OUT_OF_MEMORY, NODE_FAIL, ...), "" if the
  // controller no longer knows it.
  std::string job_state(const std::string& id) const;
  // Polls job_state every 50 ms until the job has ended; its final state, or
  // "" on timeout.
  std::string wait_ended(const std::string& id, double timeout_s = 30) const;
  // Polls until the job has left PENDING (RUNNING, or already ended); the
  // state, or "" on timeout.
  std::string wait_started(const std::string& id, double timeout_s = 30) const;
  // The value of Key in `scontrol -o show job ID` ("JobState", "ExitCode",
  // "Reason", "NodeList"), "" if absent.
  std::string job_field(const std::string& id, const std::string& key) const;

  // The last lines of every daemon's log, for a failure message.
  std::string log_tail(int lines = 15) const;

 private:
  struct Daemon {
    std::string name;  // munged, slurmctld, n1 ...
    std::vector<std::string> argv;
    std::filesystem::path out;  // its stdout and stderr
    pid_t pid = 0;
  };

  bool spawn(Daemon& d, std::string* why);
  void terminate(Daemon& d, double grace_s);
  bool wait_nodes_idle(double timeout_s, std::string* why);
  void sweep_leftovers();
  std::vector<std::pair<std::string, std::string>> effective_conf() const;
  std::string conf_value(const std::string& key) const;
  std::string conf_text() const;
  bool fail(std::string* why, const std::string& message);

  std::vector<std::pair<std::string, std::string>> conf_;
  std::filesystem::path dir_;
  int ctld_port_ = 0;
  std::vector<int> node_ports_;
  Daemon munged_, ctld_;
  std::vector<Daemon> slurmd_;
  std::vector<pid_t> started_;
  std::vector<pid_t> swept_;
  std::vector<std::string> node_start_times_;  // SlurmdStartTime at the last (re)start
};

}  // namespace cgview::test
