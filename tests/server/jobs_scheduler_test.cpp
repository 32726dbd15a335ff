// The JobScheduler in-process (with the test worker): fairness across owners.
#include <algorithm>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "jobs.h"
#include "mesh_service.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

TEST(JobScheduler, RoundRobinAcrossOwners) {
  const auto dir = test::temp_dir("jobs-fairness");
  Store store(dir);
  MeshService meshes(store);
  std::ifstream f(test::sample("sphere.off"), std::ios::binary);
  std::stringstream bytes;
  bytes << f.rdbuf();
  const MeshRecord mesh = meshes.upload("sphere.off", "", bytes.str());
  JobConfig config;
  config.worker = test::bin("cgview-worker-test");
  config.max_workers = 1;
  JobScheduler jobs(meshes, config);
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> started;
  int ended = 0;
  jobs.on_event = [&](const json& e) {
    std::lock_guard lock(m);
    // A job's first running event marks its start (a slow worker may report
    // progress 0 again before its first step).
    if (e["type"] == "job_progress" && e["job"]["state"] == "running" &&
        std::find(started.begin(), started.end(), e["job"]["id"].get<std::string>()) == started.end())
      started.push_back(e["job"]["id"]);
    if (e["type"] == "job_done" || e["type"] == "job_failed") ++ended;
    cv.notify_all();
  };
  auto submit = [&](const std::string& owner, double seconds) {
    return jobs.submit({{"algorithm", "test_sleep"}, {"inputs", {{"mesh", mesh.id}}}, {"params", {{"seconds", seconds}}}},
                       owner)["id"].get<std::string>();
  };
  // Queued before the scheduler starts: alice has three, bob one, carol one.
  const std::string a1 = submit("alice", 0.01), a2 = submit("alice", 0.02), a3 = submit("alice", 0.03);
  const std::string b1 = submit("bob", 0.01), c1 = submit("carol", 0.01);
  jobs.start();
  std::unique_lock lock(m);
  ASSERT_TRUE(cv.wait_for(lock, 30s, [&] { return ended == 5; }));
  EXPECT_EQ(started, (std::vector<std::string>{a1, b1, c1, a2, a3}));
  EXPECT_EQ(jobs.workers_started(), 5u);
}

}  // namespace
}  // namespace cgview::server
