// Jobs through the Slurm executor, against a real three-node cluster on this
// machine (slurm_cluster.h) and the real cgview-server: jobs land on every
// node, their results equal the local executor's byte for byte, and cancel,
// the time and memory limits, a crash, a killed node, a server killed and
// started again, and a job Slurm forgot each end as a person expects; a
// user's plugin is built and run on the nodes in the sandbox; a job memory
// no node has, and nodes that do not see the shared data directory, are
// said in those words (at the start, or as the job's error).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sched.h>
#include <signal.h>
#include <stdlib.h>
#include <sys/mount.h>

#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "server_harness.h"
#include "slurm_cluster.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

class SlurmJobs : public ServerFixture {
 protected:
  // Its data outside /tmp, where a job could see it were it not hidden.
  SlurmJobs() : ServerFixture("slurm-jobs-", true) {}

  void SetUp() override {
    ServerFixture::SetUp();
    std::string why;
    if (!SlurmCluster::available(&why)) GTEST_SKIP() << why;
    // Ended jobs leave the controller's memory after 2 s (a job "forgotten").
    cluster_.set_conf("MinJobAge", "2");
    // A short path: munge's socket path is limited to 108 bytes.
    const std::filesystem::path cluster_dir = temp_dir("sj");
    // A requeued job may start again after the credential lifetime (Slurm's
    // default 120 s): 10 s keeps the killed-node test short.
    cluster_.set_conf("AuthInfo", "socket=" + (cluster_dir / "munge" / "munge.socket").string() + ",cred_expire=10");
    ASSERT_TRUE(cluster_.start(cluster_dir, 3, &why)) << why;
    ::setenv("SLURM_CONF", cluster_.conf().c_str(), 1);  // the server and its sbatch read it
  }
  void TearDown() override {
    server_.kill_now();
    if (private_data_) ::umount2(data_.c_str(), MNT_DETACH);
    cluster_.stop();
    ::unsetenv("SLURM_CONF");
    ServerFixture::TearDown();
  }

  // The server with the Slurm executor (the test worker), polling Slurm every 0.2 s.
  bool start(std::vector<std::string> extra = {}, const fs::path& data = {}, json slurm = json::object()) {
    slurm["poll_s"] = 0.2;
    slurm["max_jobs"] = 50;
    write_text(dir_ / "config.json", json{{"slurm", slurm}}.dump());
    std::vector<std::string> args = {"--worker", bin("cgview-worker-test"),       "--executor",      "slurm",
                                     "--config", (dir_ / "config.json").string(), "--job-memory-mb", "2048"};
    args.insert(args.end(), extra.begin(), extra.end());
    return server_.start(data.empty() ? data_ : data, args, dir_);
  }
  std::string upload(const std::string& sample_name) {
    const auto r =
        http_call(port(), Method::post, "/api/v1/meshes?name=" + sample_name, read_bytes(sample(sample_name)));
    EXPECT_EQ(r.status, 201u) << r.body;
    return r.body_json().value("id", "");
  }
  json submit(const std::string& mesh, const std::string& algorithm, const json& params = json::object()) {
    const auto r = http_call(port(), Method::post, "/api/v1/jobs",
                             json{{"algorithm", algorithm}, {"inputs", {{"mesh", mesh}}}, {"params", params}}.dump());
    EXPECT_EQ(r.status, 201u) << r.body;
    return r.body_json();
  }
  json get(const std::string& id) { return http_get(port(), "/api/v1/jobs/" + id).body_json(); }
  json wait_end(const std::string& id, std::chrono::seconds limit = 60s) {
    const json j = wait_job_end(port(), id, limit);
    const std::string s = j.value("state", "");
    if (s == "queued" || s == "running") ADD_FAILURE() << "the cluster's log:\n" << cluster_.log_tail();
    return j;
  }
  json wait_running(const std::string& id, std::chrono::seconds limit = 30s) {
    const auto deadline = Clock::now() + limit;
    json j;
    while (Clock::now() < deadline) {
      j = get(id);
      if (j.value("state", "") == "running" && j.value("progress", 0.0) > 0) return j;
      std::this_thread::sleep_for(20ms);
    }
    ADD_FAILURE() << "job " << id << " never ran: " << j.dump();
    return j;
  }
  // The hostile plugin (tests/server/plugins/escape.cpp) saved and built
  // on the cluster: its build job as it ended, the plugin's id as "plugin".
  json build_escape() {
    const std::string source = read_bytes(fs::path(CGVIEW_SOURCE_DIR) / "tests/server/plugins/escape.cpp");
    const auto made =
        http_call(port(), Method::post, "/api/v1/plugins", json{{"name", "escape"}, {"source", source}}.dump());
    EXPECT_EQ(made.status, 201u) << made.body;
    const std::string plugin = made.body_json().value("id", "");
    const auto build = http_call(port(), Method::post, "/api/v1/plugins/" + plugin + "/build", "");
    EXPECT_EQ(build.status, 202u) << build.body;
    json built = wait_end(build.body_json().value("id", ""), 120s);
    built["plugin"] = plugin;
    return built;
  }
  // The Slurm job of a CGView job, by its name (cgview-ID): its id, or "".
  std::string slurm_id(const std::string& job) {
    std::string out = cluster_.run("squeue --noheader --states=all --name=cgview-" + job + " --format=%i");
    while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
    return out;
  }
  std::string artifact(const std::string& job, const std::string& name, const std::string& format) {
    const auto r = http_get(port(), "/api/v1/jobs/" + job + "/artifacts/" + name + "?format=" + format);
    EXPECT_EQ(r.status, 200u) << r.body;
    return r.body;
  }

  // data_ becomes a tmpfs that this process and the server see, and the
  // cluster's nodes (started before, in the first mount namespace) do not.
  bool hide_data_from_the_nodes() {
    fs::create_directories(data_);
    if (::unshare(CLONE_NEWNS) != 0) return false;
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) return false;
    private_data_ = ::mount("tmpfs", data_.c_str(), "tmpfs", 0, "size=256m") == 0;
    return private_data_;
  }
  // Waits (30 s at most) until the controller no longer knows the Slurm job.
  bool forgotten(const std::string& slurm_job) {
    const auto deadline = Clock::now() + 30s;
    while (Clock::now() < deadline && !cluster_.job_state(slurm_job).empty()) std::this_thread::sleep_for(200ms);
    return cluster_.job_state(slurm_job).empty();
  }
  // The job's token, as its batch script carries it (scontrol write batch_script).
  std::string token_of(const std::string& slurm_job) {
    const std::string script = cluster_.run("scontrol write batch_script " + slurm_job + " -");
    const auto at = script.find("Authorization: Bearer ");
    if (at == std::string::npos) return "";
    const auto from = at + 22;
    return script.substr(from, script.find('\'', from) - from);
  }

  SlurmCluster cluster_;
  bool private_data_ = false;
};

TEST_F(SlurmJobs, JobsLandOnEveryNodeAndResultsEqualTheLocalExecutorsByteForByte) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  // Six jobs of a second: each node has 2 CPUs, so all three are used.
  std::vector<std::string> sleepers;
  for (int i = 0; i < 6; ++i) sleepers.push_back(submit(mesh, "test_sleep", {{"seconds", 1.5 + 0.01 * i}})["id"]);
  const json sdf = submit(mesh, "sdf");
  const json vox = submit(mesh, "voxelize");
  std::set<std::string> nodes;
  std::map<std::string, std::string> slurm_ids;  // asked while each runs: the controller forgets ended jobs in 2 s
  for (const auto& id : sleepers) {
    const auto deadline = Clock::now() + 30s;
    while (Clock::now() < deadline && get(id).value("node", "").empty() && get(id).value("state", "") != "done")
      std::this_thread::sleep_for(20ms);
    nodes.insert(get(id).value("node", ""));
    slurm_ids[id] = slurm_id(id);
  }
  for (const auto& id : sleepers) EXPECT_EQ(wait_end(id).value("state", ""), "done");
  EXPECT_EQ(nodes, (std::set<std::string>{"n1", "n2", "n3"}));
  // Slurm ran each as its own batch job, named after it.
  for (const auto& id : sleepers) EXPECT_FALSE(slurm_ids[id].empty()) << id;
  ASSERT_EQ(wait_end(sdf["id"]).value("state", ""), "done") << get(sdf["id"]).dump();
  ASSERT_EQ(wait_end(vox["id"]).value("state", ""), "done") << get(vox["id"]).dump();
  const std::string sdf_slurm = artifact(sdf["id"], "sdf", "f32");
  const json vox_job = get(vox["id"]);
  ASSERT_FALSE(vox_job["artifacts"].empty());
  const std::string vox_name = vox_job["artifacts"][0]["name"];
  const std::string vox_slurm = artifact(vox["id"], vox_name, "nrrd");
  server_.kill_now();

  // The same jobs through the local executor.
  ::unsetenv("SLURM_CONF");
  ASSERT_TRUE(server_.start(dir_ / "local-data", {"--worker", bin("cgview-worker-test")}, dir_));
  const std::string mesh2 = upload("sphere.off");
  const json sdf2 = submit(mesh2, "sdf");
  const json vox2 = submit(mesh2, "voxelize");
  ASSERT_EQ(wait_end(sdf2["id"]).value("state", ""), "done");
  ASSERT_EQ(wait_end(vox2["id"]).value("state", ""), "done");
  EXPECT_TRUE(artifact(sdf2["id"], "sdf", "f32") == sdf_slurm) << "sdf differs between the executors";
  EXPECT_TRUE(artifact(vox2["id"], vox_name, "nrrd") == vox_slurm) << "the voxel grid differs between the executors";
  EXPECT_GT(sdf_slurm.size(), 100u);
}

TEST_F(SlurmJobs, APluginIsBuiltAndRunOnTheNodesInTheSandbox) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  const json built = build_escape();
  const std::string plugin = built.value("plugin", "");
  ASSERT_EQ(built.value("state", ""), "done") << built.dump();
  EXPECT_FALSE(slurm_id(built["id"]).empty()) << "the build ran on the cluster";
  auto attempt = [&](const std::string& what, const std::string& target) {
    const auto r = http_call(port(), Method::post, "/api/v1/jobs",
                             json{{"algorithm", "escape"},
                                  {"plugin", plugin},
                                  {"inputs", {{"mesh", mesh}}},
                                  {"params", {{"attempt", what}, {"target", target}}}}
                                 .dump());
    EXPECT_EQ(r.status, 201u) << r.body;
    return wait_end(r.body_json().value("id", ""));
  };
  // On a node, as on the server: the data directory is not there, nor a network.
  const json read = attempt("read_file", (data_ / "cgview.db").string());
  EXPECT_EQ(read.value("state", ""), "failed") << read.dump();
  EXPECT_NE(read.value("error", json("")).get<std::string>().find("not visible"), std::string::npos) << read.dump();
  EXPECT_FALSE(slurm_id(read["id"]).empty()) << "it ran on the cluster";
  const json net = attempt("connect_local", std::to_string(port()));
  EXPECT_NE(net.value("error", json("")).get<std::string>().find("a job has no network"), std::string::npos)
      << net.dump();
  // Links left where a batch script once wrote the exit status, as the
  // server's user after the sandbox, reach nothing: the script writes
  // outside the job's directory.
  const fs::path precious = dir_ / "precious.txt";
  write_text(precious, "the server's own file\n");
  const json exit_links = attempt("link_exit", precious.string());
  EXPECT_EQ(exit_links.value("state", ""), "failed") << exit_links.dump();
  EXPECT_EQ(read_bytes(precious), "the server's own file\n");
  // It failed as a sandboxed job does: the sandbox's rule is named.
  EXPECT_NE(read.value("error", json("")).get<std::string>().find("(the sandbox: "), std::string::npos) << read.dump();
}

// A job that leaves a link as its tmp/ and is requeued by the cluster
// (scontrol requeue, as after a node failure or preemption) runs again in
// a fresh directory its batch script makes: the link is never bound as the
// new run's /tmp.
TEST_F(SlurmJobs, ARequeuedRunGetsAFreshDirectoryNotTheLinkAnEarlierRunLeft) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  const std::string plugin = build_escape().value("plugin", "");
  ASSERT_FALSE(plugin.empty());
  const auto r = http_call(port(), Method::post, "/api/v1/jobs",
                           json{{"algorithm", "escape"},
                                {"plugin", plugin},
                                {"inputs", {{"mesh", mesh}}},
                                {"params", {{"attempt", "link_tmp"}}}}
                               .dump());
  ASSERT_EQ(r.status, 201u) << r.body;
  const std::string id = r.body_json().value("id", "");
  const fs::path run = data_ / "runs" / id;
  // Run N's link: its batch script makes a fresh work/ before it marks the run started (started.N).
  auto linked_by_run = [&](int n, std::chrono::seconds limit) {
    for (const auto until = Clock::now() + limit; Clock::now() < until; std::this_thread::sleep_for(50ms)) {
      if (fs::exists(run / ("started." + std::to_string(n + 1)))) return false;
      if (fs::exists(run / ("started." + std::to_string(n))) && fs::is_symlink(run / "work" / "tmp")) return true;
      if (get(id).value("state", "") == "done") break;  // escaped
    }
    return false;
  };
  ASSERT_TRUE(linked_by_run(0, 60s)) << get(id).dump();
  const std::string sid = slurm_id(id);
  cluster_.run("scontrol requeue " + sid);
  EXPECT_TRUE(linked_by_run(1, 60s)) << "no second run planted its own link: " << get(id).dump() << cluster_.log_tail();
  EXPECT_NE(get(id).value("state", ""), "done") << "a run saw the server's data as its /tmp";
  EXPECT_EQ(slurm_id(id), sid) << "requeued by Slurm, not submitted again";
  EXPECT_EQ(http_call(port(), Method::delete_, "/api/v1/jobs/" + id).status, 200u);
  EXPECT_EQ(wait_end(id).value("state", ""), "cancelled");
}

TEST_F(SlurmJobs, CancelStopsTheSlurmJobWithinSeconds) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  const json job = submit(mesh, "test_sleep", {{"seconds", 60}});
  wait_running(job["id"]);
  const std::string sid = slurm_id(job["id"]);
  ASSERT_FALSE(sid.empty());
  const auto r = http_call(port(), Method::delete_, "/api/v1/jobs/" + job["id"].get<std::string>());
  ASSERT_EQ(r.status, 200u) << r.body;
  EXPECT_EQ(r.body_json().value("state", ""), "cancelled");
  EXPECT_EQ(cluster_.wait_ended(sid, 10), "CANCELLED");
  EXPECT_EQ(get(job["id"]).value("state", ""), "cancelled");
}

TEST_F(SlurmJobs, TimeMemoryAndACrashFailWithTheirReasons) {
  // 5 s, not 2: on a loaded machine the memory hog once ran out of time
  // before it reached its 300 MB.
  ASSERT_TRUE(start({"--job-timeout-s", "5", "--job-memory-mb", "300"}));
  const std::string mesh = upload("sphere.off");
  const json slow = submit(mesh, "test_sleep", {{"seconds", 60}});
  const json hog = submit(mesh, "test_memory_hog");
  const json crash = submit(mesh, "test_segfault");
  EXPECT_EQ(wait_end(slow["id"]).value("error", ""), "exceeded its time limit of 5 s");
  EXPECT_EQ(wait_end(hog["id"]).value("error", ""), "exceeded its memory limit of 300 MB");
  EXPECT_EQ(wait_end(crash["id"]).value("error", ""), "killed by signal SIGSEGV");
  for (const auto& j : {slow, hog, crash}) EXPECT_EQ(get(j["id"]).value("state", ""), "failed");
}

TEST_F(SlurmJobs, PendingJobsSayWhyTheyWait) {
  ASSERT_TRUE(start({"--job-cpus", "2"}));
  const std::string mesh = upload("sphere.off");
  // Three nodes of 2 CPUs hold three 2-CPU jobs: the fourth waits for resources.
  std::vector<std::string> ids;
  for (int i = 0; i < 4; ++i) ids.push_back(submit(mesh, "test_sleep", {{"seconds", 3}})["id"]);
  bool seen_waiting = false;
  const auto deadline = Clock::now() + 20s;
  while (Clock::now() < deadline && !seen_waiting) {
    for (const auto& id : ids) {
      const json j = get(id);
      if (j.value("state", "") == "queued" && j.value("stage", "").rfind("waiting for the cluster: Resources", 0) == 0)
        seen_waiting = true;
    }
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_TRUE(seen_waiting);
  for (const auto& id : ids) EXPECT_EQ(wait_end(id).value("state", ""), "done");
}

TEST_F(SlurmJobs, OwnersTakeTurnsBeforeTheirJobsReachTheCluster) {
  fs::create_directories(data_);
  const std::string alice = server_command(data_, "user add alice"), bob = server_command(data_, "user add bob");
  // Three 2-CPU jobs fill the cluster; one more may wait in it.
  ASSERT_TRUE(start({"--auth", "required", "--job-cpus", "2"}, {}, {{"max_pending", 1}}));
  auto job_as = [&](const std::string& token, const std::string& mesh, double seconds) {
    const auto r = call_as(
        port(), token, "POST", "/api/v1/jobs",
        json{{"algorithm", "test_sleep"}, {"inputs", {{"mesh", mesh}}}, {"params", {{"seconds", seconds}}}}.dump());
    EXPECT_EQ(r.status, 201u) << r.body;
    return r.body_json().value("id", "");
  };
  auto mesh_of = [&](const std::string& token) {
    return call_as(port(), token, "POST", "/api/v1/meshes?name=sphere.off", read_bytes(sample("sphere.off")))
        .body_json()
        .value("id", "");
  };
  const std::string a_mesh = mesh_of(alice), b_mesh = mesh_of(bob);
  std::vector<std::string> a_jobs;
  // Each long enough that the first ends well after the 1.5 s of quiet below,
  // on a loaded machine too (at 2 s, a slow sbatch let her fifth in first).
  for (int i = 0; i < 8; ++i) a_jobs.push_back(job_as(alice, a_mesh, 4.5 + 0.01 * i));
  // Each job's Slurm id, noted while the controller knows it (MinJobAge 2 s).
  std::map<std::string, long> sid;
  auto note_slurm_ids = [&] {
    std::istringstream rows(cluster_.run("squeue --noheader --states=all --format='%i|%j'"));
    for (std::string row; std::getline(rows, row);)
      if (const auto bar = row.find("|cgview-"); bar != std::string::npos)
        sid.emplace(row.substr(bar + 8), std::stol(row.substr(0, bar)));
  };
  // Bob comes once Alice's jobs stop reaching the cluster (1.5 s without a new one).
  auto changed = Clock::now();
  for (std::size_t seen = 0; Clock::now() - changed < 1500ms;) {
    note_slurm_ids();
    if (sid.size() != seen || seen == 0) seen = sid.size(), changed = Clock::now();
    std::this_thread::sleep_for(50ms);
  }
  // Not Alice's parameters: a result she already has would answer Bob from the cache.
  const std::string b_job = job_as(bob, b_mesh, 4.95);
  auto ended = [&](const std::string& id) {
    const std::string s = call_as(port(), alice, "GET", "/api/v1/jobs/" + id).body_json().value("state", "");
    return s == "done" || s == "failed";
  };
  const auto until = Clock::now() + 90s;
  while (Clock::now() < until &&
         !(ended(a_jobs.back()) &&
           call_as(port(), bob, "GET", "/api/v1/jobs/" + b_job).body_json().value("state", "") == "done")) {
    note_slurm_ids();
    std::this_thread::sleep_for(100ms);
  }
  // Bob's one job reached Slurm (its ids grow with submission) before
  // Alice's fifth: it waited in CGView's fair queue, not behind her eight in Slurm's.
  ASSERT_TRUE(sid.count(b_job)) << call_as(port(), bob, "GET", "/api/v1/jobs/" + b_job).body << "\n"
                                << cluster_.run("squeue --noheader --states=all --format='%i|%j'");
  for (int i = 4; i < 8; ++i) {
    ASSERT_TRUE(sid.count(a_jobs[i])) << i;
    EXPECT_LT(sid[b_job], sid[a_jobs[i]]) << "alice's job " << i;
  }
}

TEST_F(SlurmJobs, AServerKilledAndStartedAgainEndsEachJobExactlyOnce) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  std::vector<std::string> ids;
  for (int i = 0; i < 3; ++i) ids.push_back(submit(mesh, "test_sleep", {{"seconds", 3 + 0.01 * i}})["id"]);
  for (const auto& id : ids) wait_running(id);
  std::vector<std::string> sids;
  for (const auto& id : ids) sids.push_back(slurm_id(id));
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  ASSERT_TRUE(start());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const json j = wait_end(ids[k]);
    EXPECT_EQ(j.value("state", ""), "done") << j.dump();
    EXPECT_EQ(j["artifacts"].size(), 1u);
    // The same Slurm job, run once: no second submission of it.
    EXPECT_EQ(slurm_id(ids[k]), sids[k]);
  }
  EXPECT_EQ(artifact(ids[0], "index", "json").empty(), false);
}

// A job whose run ended with its result on disk, but which the cluster
// then holds (as after munged was away when the run ended: "launch failed
// requeued held"), is settled from that result, not left waiting for good.
// The worker here (unsandboxed, so that it reaches the controller) writes
// its run's exit status itself, as the batch script would after it, and
// has its job requeued and held before the script ends (deaf to the
// SIGTERM that comes then: killed by the SIGKILL after it, with the script,
// which so never writes a status of its own over the run's).
TEST_F(SlurmJobs, AJobTheClusterHoldsAfterItsRunEndedIsSettledFromItsResult) {
  const fs::path worker = dir_ / "holding-worker";
  write_text(worker, "#!/bin/sh\n[ \"$1\" = --list ] && exec " + bin("cgview-worker-test") + " --list\n" +
                         bin("cgview-worker-test") +
                         " \"$@\"; rc=$?\necho $rc > worker.exit.0\nSLURM_CONF=" + cluster_.conf().string() +
                         " scontrol requeuehold \"$SLURM_JOB_ID\"\ntrap '' TERM\nsleep 60\nexit $rc\n");
  ::chmod(worker.c_str(), 0755);
  ASSERT_TRUE(start({"--worker", worker.string()}, {}, {{"sandbox", false}}));
  const std::string mesh = upload("sphere.off");
  const json job = submit(mesh, "test_sleep", {{"seconds", 0.5}});
  const std::string id = job["id"];
  // Held in the cluster: the job waits again, saying why.
  auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  json j;
  for (const auto until = Clock::now() + 30s; Clock::now() < until; std::this_thread::sleep_for(20ms)) {
    j = get(id);
    if (lower(j.value("stage", "")).find("held") != std::string::npos || j.value("state", "") == "done") break;
  }
  EXPECT_NE(lower(j.value("stage", "")).find("held"), std::string::npos) << j.dump() << cluster_.log_tail();
  const json end = wait_end(id, 40s);
  EXPECT_EQ(end.value("state", ""), "done") << end.dump();
  EXPECT_EQ(artifact(id, "index", "f32").size(), 4 * 162u) << "its result, one value per vertex";
  EXPECT_EQ(cluster_.run("squeue --noheader --states=PENDING,RUNNING --name=cgview-" + id), "")
      << "the held Slurm job was left in the cluster";
}

TEST_F(SlurmJobs, AJobSlurmForgotFailsSayingSo) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  const json job = submit(mesh, "test_sleep", {{"seconds", 60}});
  wait_running(job["id"]);
  const std::string sid = slurm_id(job["id"]);
  ASSERT_FALSE(sid.empty());
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  // While the server is down its job is cancelled behind its back and
  // leaves the controller's memory (MinJobAge 2 s).
  cluster_.run("scancel " + sid);
  ASSERT_TRUE(forgotten(sid)) << "the controller still knows the job";
  // Lost without a trace, as with its node: the exit status its batch script
  // may have written on the way down (a sandboxed worker's bwrap ends in
  // time for it to) is gone too.
  std::error_code ec;
  fs::remove(data_ / "runs" / job["id"].get<std::string>() / "worker.exit.0", ec);
  ASSERT_TRUE(start());
  const json j = wait_end(job["id"], 20s);
  EXPECT_EQ(j.value("state", ""), "failed");
  EXPECT_EQ(j.value("error", ""), "Slurm no longer knows job " + sid + " (purged, or lost with its node)");
}

TEST_F(SlurmJobs, AJobSlurmForgotRunsAgainWhenTheSettingSaysRequeue) {
  const json requeue = {{"on_lost", "requeue"}};
  ASSERT_TRUE(start({}, {}, requeue));
  const std::string mesh = upload("sphere.off");
  const json job = submit(mesh, "test_sleep", {{"seconds", 2}});
  wait_running(job["id"]);
  const std::string sid = slurm_id(job["id"]);
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  cluster_.run("scancel " + sid);
  ASSERT_TRUE(forgotten(sid)) << "the controller still knows the job";
  ASSERT_TRUE(start({}, {}, requeue));
  const json j = wait_end(job["id"], 30s);
  EXPECT_EQ(j.value("state", ""), "done") << j.dump();
  const std::string again = slurm_id(job["id"]);
  EXPECT_FALSE(again.empty());
  EXPECT_NE(again, sid) << "a new Slurm job ran it";
}

// A node that dies is marked down after SlurmdTimeout: 10 s here, to keep
// the test under a minute (the other tests keep the harness's 20 s, which a
// slurmd slowed by a busy machine does not miss).
class SlurmJobsNodeDeath : public SlurmJobs {
 protected:
  void SetUp() override {
    cluster_.set_conf("SlurmdTimeout", "10");
    SlurmJobs::SetUp();
  }
};

TEST_F(SlurmJobsNodeDeath, AJobOnAKilledNodeIsRequeuedByTheClusterAndRunsElsewhere) {
  ASSERT_TRUE(start());
  const std::string mesh = upload("sphere.off");
  const json job = submit(mesh, "test_sleep", {{"seconds", 4}});
  const std::string id = job["id"];
  const json running = wait_running(id);
  const std::string node = running.value("node", "");
  ASSERT_FALSE(node.empty());
  const std::string sid = slurm_id(id);
  // The node dies: its slurmd and the job's processes on it.
  cluster_.kill_node(std::stoi(node.substr(1)));
  cluster_.run("pkill -KILL -f 'slurmstepd: \\[" + sid + "\\.' ; pkill -KILL -f 'jobs/" + id + "/job.json'");
  // SlurmdTimeout=10: the controller marks the node down in about 15 s
  // and requeues the job (JobRequeue=1, Slurm's default): it waits
  // again, then runs on another node to its end.
  bool waited_again = false;
  const auto deadline = Clock::now() + 120s;
  json j;
  while (Clock::now() < deadline) {
    j = get(id);
    const std::string s = j.value("state", "");
    waited_again |= s == "queued";
    if (s != "queued" && s != "running") break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_TRUE(waited_again) << j.dump();
  EXPECT_EQ(j.value("state", ""), "done") << j.dump();
  EXPECT_NE(j.value("node", ""), node) << j.dump();
  EXPECT_EQ(slurm_id(id), sid) << "requeued by Slurm, not submitted again";
}

// The harness's nodes have RealMemory=4000 (slurm_cluster.h): the
// server's default job memory, 8192 MB, fits none of them.  The server says
// so as it starts, not as each job's refusal by sbatch.
TEST_F(SlurmJobs, AJobMemoryNoNodeHasIsSaidWhenTheServerStarts) {
  write_text(dir_ / "config.json", json{{"slurm", {{"poll_s", 0.2}}}}.dump());
  const std::string command = bin("cgview-server") + " --host 127.0.0.1 --port 0 --samples none --data-dir " +
                              data_.string() + " --worker " + bin("cgview-worker-test") +
                              " --executor slurm --config " + (dir_ / "config.json").string();
  std::string out;
  EXPECT_EQ(run(command, &out), 1) << out;
  EXPECT_NE(out.find("cgview-server: error: no Slurm node has the 8192 MB of memory a job asks (the largest has "
                     "4000 MB): lower job_memory_mb (--job-memory-mb) to 4000 or less, or name in slurm.partition a "
                     "partition whose nodes have more"),
            std::string::npos)
      << out;
  // Of a partition named in slurm.partition, the same (the harness's one partition).
  write_text(dir_ / "config.json", json{{"slurm", {{"partition", "debug"}}}}.dump());
  EXPECT_EQ(run(command + " --job-memory-mb 5000", &out), 1) << out;
  EXPECT_NE(out.find("no Slurm node of partition debug has the 5000 MB of memory a job asks (the largest has 4000 MB)"),
            std::string::npos)
      << out;
  // What a node has is enough.
  ASSERT_TRUE(start({"--job-memory-mb", "4000"}));
  EXPECT_EQ(wait_end(submit(upload("sphere.off"), "test_sleep", {{"seconds", 0}})["id"]).value("state", ""), "done");
}

// A cluster that did not answer as the server started is asked again at
// the first launch: that job fails with the same words.
TEST_F(SlurmJobs, AJobMemoryNoNodeHasFailsTheFirstJobWhereTheClusterDidNotAnswerAtTheStart) {
  // An sinfo that fails until the marker is there, then is Slurm's own.
  const fs::path tools = dir_ / "tools", marker = dir_ / "sinfo-answers";
  fs::create_directories(tools);
  std::string sinfo = cluster_.run("command -v sinfo");
  sinfo.erase(sinfo.find('\n'));
  write_text(tools / "sinfo", "#!/bin/sh\n[ -e '" + marker.string() + "' ] && exec '" + sinfo + "' \"$@\"\nexit 1\n");
  fs::permissions(tools / "sinfo", fs::perms::owner_all);
  const std::string path = ::getenv("PATH");
  ::setenv("PATH", (tools.string() + ":" + path).c_str(), 1);
  const bool started = start({"--job-memory-mb", "6000"});
  ::setenv("PATH", path.c_str(), 1);
  ASSERT_TRUE(started);
  write_text(marker, "");
  const json j = wait_end(submit(upload("sphere.off"), "test_sleep", {{"seconds", 0}})["id"]);
  EXPECT_EQ(j.value("state", ""), "failed");
  EXPECT_EQ(j.value("error", ""),
            "no Slurm node has the 6000 MB of memory a job asks (the largest has 4000 MB): lower job_memory_mb "
            "(--job-memory-mb) to 4000 or less, or name in slurm.partition a partition whose nodes have more");
}

// The data directory is shared by default (slurm.shared_data): where the
// nodes do not see it, the job's error says so, not Slurm's "JobLaunchFailure".
TEST_F(SlurmJobs, NodesThatDoNotSeeTheSharedDataDirectorySaySoInTheJobsError) {
  if (!hide_data_from_the_nodes()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root: unshare, mount)";
  ASSERT_TRUE(start());
  const json j = wait_end(submit(upload("sphere.off"), "test_sleep", {{"seconds", 0}})["id"]);
  EXPECT_EQ(j.value("state", ""), "failed");
  const std::string error = j.value("error", "");
  EXPECT_EQ(error.rfind("the Slurm nodes cannot see the data directory " + data_.string() +
                            " that slurm.shared_data says they share (node n",
                        0),
            0u)
      << error;
  EXPECT_NE(error.find("): mount it at the same path on every node, or set slurm.shared_data to false"),
            std::string::npos)
      << error;
}

TEST_F(SlurmJobs, WithoutASharedDirectoryWorkersFetchInputsAndSendResultsWithTheirJobsToken) {
  if (!hide_data_from_the_nodes()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root: unshare, mount)";
  ASSERT_TRUE(start({}, {}, {{"shared_data", false}}));
  const std::string mesh = upload("sphere.off");
  // The nodes see an empty directory where the server keeps its data.
  ASSERT_TRUE(fs::exists(data_ / "blobs"));
  const fs::path seen_by_node =
      fs::path("/proc") / std::to_string(cluster_.slurmd_pid(1)) / "root" / data_.relative_path();
  EXPECT_TRUE(fs::is_directory(seen_by_node)) << seen_by_node;
  EXPECT_TRUE(fs::is_empty(seen_by_node)) << seen_by_node;
  const json sdf = submit(mesh, "sdf");
  const json slow = submit(mesh, "test_sleep", {{"seconds", 4}});
  wait_running(slow["id"]);  // its progress came back over the API
  const std::string sid = slurm_id(slow["id"]);
  const std::string token = token_of(sid);
  ASSERT_EQ(token.size(), 64u) << cluster_.run("scontrol write batch_script " + sid + " -");
  // No command line holds it, which any local user reads in /proc: its
  // batch script hands it to curl in a file (curl runs each second meanwhile).
  for (const auto until = Clock::now() + 1500ms; Clock::now() < until; std::this_thread::sleep_for(5ms))
    for (const auto& [pid, cmdline] : processes_naming(token)) ADD_FAILURE() << "on a command line: " << cmdline;
  const std::string base = "/api/v1/worker/jobs/" + slow["id"].get<std::string>();
  // The token reads its own job's inputs, and nothing else.
  EXPECT_EQ(call_as(port(), token, "GET", base + "/inputs/mesh").body, read_bytes(data_ / "blobs" / (mesh + ".off")));
  expect_error(call_as(port(), token, "GET", "/api/v1/worker/jobs/" + sdf["id"].get<std::string>() + "/inputs/mesh"),
               401, "unauthorized");
  std::string forged = token;  // one hex digit changed: a token that starts with '0' must not stay the same
  forged[0] = forged[0] == '0' ? '1' : '0';
  expect_error(call_as(port(), forged, "GET", base + "/spec"), 401, "unauthorized");
  expect_error(call_as(port(), token, "PUT", base + "/files/job.json", "{}"), 400, "invalid_mesh");
  EXPECT_EQ(call_as(port(), token, "GET", "/api/v1/meshes").status, 401u) << "a job's token is not a user's";

  const json done = wait_end(sdf["id"]);
  ASSERT_EQ(done.value("state", ""), "done") << done.dump();
  EXPECT_EQ(wait_end(slow["id"]).value("state", ""), "done");
  // The token died with its job.
  expect_error(call_as(port(), token, "GET", base + "/spec"), 401, "unauthorized");
  const std::string field = artifact(sdf["id"], "sdf", "f32");
  server_.kill_now();

  // The same result as the local executor's.
  ASSERT_TRUE(server_.start(dir_ / "local-data", {"--worker", bin("cgview-worker-test")}, dir_));
  const json local = submit(upload("sphere.off"), "sdf");
  ASSERT_EQ(wait_end(local["id"]).value("state", ""), "done");
  EXPECT_TRUE(artifact(local["id"], "sdf", "f32") == field) << "sdf differs between the executors";
}

TEST_F(SlurmJobs, WithoutASharedDirectoryCancelAndCrashesBehaveAsWithOne) {
  if (!hide_data_from_the_nodes()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root: unshare, mount)";
  ASSERT_TRUE(start({"--job-memory-mb", "300"}, {}, {{"shared_data", false}}));
  const std::string mesh = upload("sphere.off");
  const json slow = submit(mesh, "test_sleep", {{"seconds", 60}});
  const json crash = submit(mesh, "test_segfault");
  const json hog = submit(mesh, "test_memory_hog");
  wait_running(slow["id"]);
  const std::string sid = slurm_id(slow["id"]);
  ASSERT_EQ(http_call(port(), Method::delete_, "/api/v1/jobs/" + slow["id"].get<std::string>()).status, 200u);
  EXPECT_EQ(cluster_.wait_ended(sid, 10), "CANCELLED");
  EXPECT_EQ(wait_end(crash["id"]).value("error", ""), "killed by signal SIGSEGV");
  EXPECT_EQ(wait_end(hog["id"]).value("error", ""), "exceeded its memory limit of 300 MB");
}

}  // namespace
}  // namespace cgview::test
