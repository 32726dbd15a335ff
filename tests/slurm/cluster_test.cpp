// The Slurm test cluster itself (tests/slurm/slurm_cluster.h): jobs land on
// the node asked for, and the way Slurm 22.05 reports a memory kill, a cancel,
// a signal and an exit status, in squeue, scontrol and `sacct -c` (jobcomp
// file, no slurmdbd).  These are the facts the Slurm executor relies on.
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <chrono>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "slurm_cluster.h"
#include "test_support.h"

namespace fs = std::filesystem;
using cgview::test::SlurmCluster;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// No such process, or only its zombie (whoever its parent now is reaps it).
bool gone(pid_t pid) {
  if (::kill(pid, 0) != 0 && errno == ESRCH) return true;
  const std::string stat = slurp("/proc/" + std::to_string(pid) + "/stat");
  const auto paren = stat.rfind(')');
  return paren == std::string::npos || (paren + 2 < stat.size() && stat[paren + 2] == 'Z');
}

// One line of `sacct -c` (the jobcomp file) for a job: "STATE|EXITCODE|NODELIST".
std::string sacct_line(const SlurmCluster& c, const std::string& id) {
  std::string out = c.run("sacct -c -n -P -j " + id + " -o State,ExitCode,NodeList");
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out;
}

// The jobcomp file is written when the job ends, a moment after squeue shows it.
std::string wait_sacct_line(const SlurmCluster& c, const std::string& id) {
  std::string line;
  for (int i = 0; i < 100 && (line = sacct_line(c, id)).empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  return line;
}

class SlurmClusterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string why;
    if (!SlurmCluster::available(&why)) GTEST_SKIP() << why;
    dir_ =
        cgview::test::temp_dir("slurm-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    ASSERT_TRUE(cluster_.start(dir_, 3, &why)) << why;
  }

  // Every daemon gone after stop(), and no process left with their logs open.
  void TearDown() override {
    const auto pids = cluster_.started_pids();
    cluster_.stop();
    for (pid_t p : pids) EXPECT_TRUE(gone(p)) << "pid " << p << " outlived stop()";
  }

  fs::path dir_;
  SlurmCluster cluster_;
};

TEST_F(SlurmClusterTest, EachJobRunsOnTheNodeAskedFor) {
  std::vector<std::string> ids;
  std::vector<double> start_s;
  for (int n = 1; n <= 3; ++n) {
    std::string why;
    const auto t0 = std::chrono::steady_clock::now();
    const std::string id = cluster_.submit("-w " + cluster_.node_name(n) + " -o " + (dir_ / "%j.out").string() +
                                               " --wrap 'hostname; echo $SLURMD_NODENAME'",
                                           &why);
    ASSERT_FALSE(id.empty()) << why;
    ASSERT_NE(cluster_.wait_started(id, 10), "");
    start_s.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    ids.push_back(id);
  }
  for (int n = 1; n <= 3; ++n) {
    const std::string& id = ids[n - 1];
    const std::string node = cluster_.node_name(n);
    ASSERT_EQ(cluster_.wait_ended(id, 10), "COMPLETED") << cluster_.log_tail();
    const std::string out = slurp(dir_ / (id + ".out"));
    EXPECT_NE(out.find("\n" + node + "\n"), std::string::npos) << out;  // after hostname
    EXPECT_EQ(cluster_.job_field(id, "NodeList"), node);
    EXPECT_EQ(cluster_.job_field(id, "ExitCode"), "0:0");
    EXPECT_EQ(wait_sacct_line(cluster_, id), "COMPLETED|0:0|" + node);
  }
  // Batch jobs start on the controller's scheduling tick (once a second with
  // sched_interval=1; the first one about 3 s after slurmctld starts): the
  // first job here waits ~1.9 s, the next ones, each submitted just after a
  // tick, ~1.0 s.  Submitted at a random moment: 0.2 to 0.9 s.
  for (double s : start_s) {
    EXPECT_LT(s, 5.0);
    RecordProperty("submit_to_start_ms", static_cast<int>(s * 1000));
    std::cout << "submit to start: " << s << " s\n";
  }
}

TEST_F(SlurmClusterTest, UnpinnedJobsSpreadOverTheNodes) {
  // Six jobs of 2 CPUs each (a whole node) that stay a second: two rounds
  // over three nodes, so each node runs some.
  std::vector<std::string> ids;
  for (int k = 0; k < 6; ++k) {
    std::string why;
    ids.push_back(cluster_.submit("-c 2 -o /dev/null --wrap 'sleep 1'", &why));
    ASSERT_FALSE(ids.back().empty()) << why;
  }
  std::set<std::string> nodes;
  for (const auto& id : ids) {
    ASSERT_EQ(cluster_.wait_ended(id, 20), "COMPLETED");
    nodes.insert(cluster_.job_field(id, "NodeList"));
  }
  EXPECT_EQ(nodes, (std::set<std::string>{"n1", "n2", "n3"}));
}

TEST_F(SlurmClusterTest, MemoryHogIsKilled) {
  std::string why;
  const std::string id =
      cluster_.submit("--mem=20 -o " + (dir_ / "%j.out").string() +
                          " --wrap 'python3 -c \"x = bytearray(400 * 1024 * 1024); import time; time.sleep(30)\"'",
                      &why);
  ASSERT_FALSE(id.empty()) << why;
  // Slurm 22.05 with jobacct_gather/linux + OverMemoryKill (no cgroups): the
  // poller SIGKILLs the step within a second or two.  Not OUT_OF_MEMORY (that
  // is the cgroup OOM path): squeue/scontrol say FAILED, Reason=JobLaunchFailure,
  // ExitCode=0:9; sacct -c says FAILED 0:9; the job's stderr has
  // "slurmstepd-n1: error: StepId=4.batch exceeded memory limit (434532352 >
  // 20971520), being killed" and "Exceeded job memory limit".
  EXPECT_EQ(cluster_.wait_ended(id, 20), "FAILED");
  EXPECT_EQ(cluster_.job_field(id, "ExitCode"), "0:9");
  EXPECT_EQ(cluster_.job_field(id, "Reason"), "JobLaunchFailure");
  const std::string line = wait_sacct_line(cluster_, id);
  EXPECT_EQ(line.substr(0, line.rfind('|')), "FAILED|0:9");
  EXPECT_NE(slurp(dir_ / (id + ".out")).find("exceeded memory limit"), std::string::npos);
}

TEST_F(SlurmClusterTest, ScancelEndsCancelled) {
  std::string why;
  const std::string id = cluster_.submit("-o /dev/null --wrap 'sleep 300'", &why);
  ASSERT_FALSE(id.empty()) << why;
  ASSERT_EQ(cluster_.wait_started(id, 10), "RUNNING");
  int rc = -1;
  const std::string out = cluster_.run("scancel " + id, &rc);
  ASSERT_EQ(rc, 0) << out;
  // scontrol: CANCELLED, Reason=None; sacct -c: CANCELLED 0:0.  ExitCode
  // depends on who dies first: 0:15 when SIGTERM kills the batch shell,
  // 143:0 when the shell outlives its `sleep` long enough to exit with
  // 128+15 itself, 1:0 seen too (both on a loaded machine).  So CGView reads
  // none of them (it knows it cancelled), and neither does this test.
  EXPECT_EQ(cluster_.wait_ended(id, 10), "CANCELLED");
  const std::string line = wait_sacct_line(cluster_, id);
  EXPECT_EQ(line.substr(0, line.rfind('|')), "CANCELLED|0:0");
}

TEST_F(SlurmClusterTest, SignalAndExitStatusAreFailed) {
  std::string why;
  const std::string segv = cluster_.submit("-o /dev/null --wrap 'kill -SEGV $$'", &why);
  ASSERT_FALSE(segv.empty()) << why;
  const std::string exit3 = cluster_.submit("-o /dev/null --wrap 'exit 3'", &why);
  ASSERT_FALSE(exit3.empty()) << why;
  // A batch script killed by a signal: FAILED, Reason=JobLaunchFailure (sic),
  // ExitCode=0:11.  An exit status: FAILED, Reason=NonZeroExitCode, 3:0.
  EXPECT_EQ(cluster_.wait_ended(segv, 10), "FAILED");
  EXPECT_EQ(cluster_.job_field(segv, "ExitCode"), "0:11");
  EXPECT_EQ(cluster_.job_field(segv, "Reason"), "JobLaunchFailure");
  EXPECT_EQ(cluster_.wait_ended(exit3, 10), "FAILED");
  EXPECT_EQ(cluster_.job_field(exit3, "ExitCode"), "3:0");
  EXPECT_EQ(cluster_.job_field(exit3, "Reason"), "NonZeroExitCode");
  std::string line = wait_sacct_line(cluster_, segv);
  EXPECT_EQ(line.substr(0, line.rfind('|')), "FAILED|0:11");
  line = wait_sacct_line(cluster_, exit3);
  EXPECT_EQ(line.substr(0, line.rfind('|')), "FAILED|3:0");
  // One squeue call for many jobs: exit_code is the raw wait status
  // (signal 11 -> 11, exit 3 -> 768).
  const std::string many = cluster_.run("squeue -h -t all -j " + segv + "," + exit3 +
                                        " -O 'JobID:|,State:|,Reason:|,NodeList:|,exit_code:|'");
  EXPECT_NE(many.find(segv + "|FAILED|JobLaunchFailure|"), std::string::npos) << many;
  EXPECT_NE(many.find("|11|"), std::string::npos) << many;
  EXPECT_NE(many.find(exit3 + "|FAILED|NonZeroExitCode|"), std::string::npos) << many;
  EXPECT_NE(many.find("|768|"), std::string::npos) << many;
}

TEST_F(SlurmClusterTest, KilledNodeRestarts) {
  const pid_t old = cluster_.slurmd_pid(2);
  cluster_.kill_node(2);
  EXPECT_TRUE(gone(old));
  EXPECT_EQ(cluster_.slurmd_pid(2), 0);
  std::string why;
  ASSERT_TRUE(cluster_.restart_node(2, &why)) << why;
  EXPECT_NE(cluster_.slurmd_pid(2), 0);
  const std::string id = cluster_.submit("-w n2 -o /dev/null --wrap true", &why);
  ASSERT_FALSE(id.empty()) << why;
  EXPECT_EQ(cluster_.wait_ended(id, 10), "COMPLETED");
}

TEST_F(SlurmClusterTest, StopEndsRunningJobsAndOrphanedSteps) {
  // A job on a node whose slurmd is then killed: its slurmstepd and the job
  // go on without it, and stop() must still end them.  (Killed within the
  // launch, about one time in eight, the slurmstepd dies too and leaves the
  // job's processes alone: stop() finds those by their environment.)
  const fs::path pid_file = dir_ / "job.pid";
  std::string why;
  const std::string id =
      cluster_.submit("-w n1 -o /dev/null --wrap 'echo $$ > " + pid_file.string() + "; exec sleep 300'", &why);
  ASSERT_FALSE(id.empty()) << why;
  ASSERT_EQ(cluster_.wait_started(id, 10), "RUNNING");
  for (int i = 0; i < 100 && slurp(pid_file).empty(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  const pid_t job = static_cast<pid_t>(std::atol(slurp(pid_file).c_str()));
  ASSERT_GT(job, 0);
  cluster_.kill_node(1);
  EXPECT_FALSE(gone(job));
  cluster_.stop();
  for (int i = 0; i < 40 && !gone(job); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_TRUE(gone(job)) << "the job's sleep (pid " << job << ") outlived stop()";
  const auto swept = cluster_.swept_pids();
  EXPECT_NE(std::find(swept.begin(), swept.end(), job), swept.end());
}

}  // namespace
