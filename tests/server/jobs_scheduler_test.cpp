// The JobScheduler in-process (with the test worker): fairness across owners,
// and the chaos algorithms' text and animation artifacts.
#include <algorithm>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "core/animation.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

// A store holding one sample mesh, and a scheduler of one test worker on it
// (not started: set on_event, then start()).
struct Scheduler {
  static MeshRecord upload(MeshService& meshes, const std::string& sample) {
    std::ifstream f(test::sample(sample), std::ios::binary);
    std::stringstream bytes;
    bytes << f.rdbuf();
    return meshes.upload(sample, "", bytes.str());
  }
  static JobConfig config() {
    JobConfig c;
    c.worker = test::bin("cgview-worker-test");
    c.max_workers = 1;
    return c;
  }
  Scheduler(const std::string& dir_name, const std::string& sample)
      : store(test::temp_dir(dir_name)), meshes(store), mesh(upload(meshes, sample)), jobs(meshes, config()) {}
  Store store;
  MeshService meshes;
  MeshRecord mesh;
  JobScheduler jobs;

  // Submits a test_sleep job on the mesh for OWNER; its id.
  std::string submit_sleep(const std::string& owner, double seconds) {
    return jobs
        .submit({{"algorithm", "test_sleep"}, {"inputs", {{"mesh", mesh.id}}}, {"params", {{"seconds", seconds}}}},
                Caller{owner, true})["id"]
        .get<std::string>();
  }
};

// The order in which a scheduler's jobs start and how many have ended, from
// its events (set as its on_event); read them under the lock.
struct StartOrder {
  explicit StartOrder(JobScheduler& jobs) {
    jobs.on_event = [this](const json& e, const Access&) {
      std::lock_guard lock(m);
      // A job's first running event marks its start (a slow worker may report
      // progress 0 again before its first step).
      if (e["type"] == "job_progress" && e["job"]["state"] == "running" &&
          std::find(started.begin(), started.end(), e["job"]["id"].get<std::string>()) == started.end())
        started.push_back(e["job"]["id"]);
      if (e["type"] == "job_done" || e["type"] == "job_failed") ++ended;
      cv.notify_all();
    };
  }
  std::mutex m;
  std::condition_variable cv;
  std::vector<std::string> started;
  int ended = 0;
};

TEST(JobScheduler, RoundRobinAcrossOwners) {
  Scheduler s("jobs-fairness", "sphere.off");
  StartOrder o(s.jobs);
  // Queued before the scheduler starts: alice has three, bob one, carol one.
  const std::string a1 = s.submit_sleep("alice", 0.01), a2 = s.submit_sleep("alice", 0.02),
                    a3 = s.submit_sleep("alice", 0.03);
  const std::string b1 = s.submit_sleep("bob", 0.01), c1 = s.submit_sleep("carol", 0.01);
  s.jobs.start();
  std::unique_lock lock(o.m);
  ASSERT_TRUE(o.cv.wait_for(lock, 30s, [&] { return o.ended == 5; }));
  EXPECT_EQ(o.started, (std::vector<std::string>{a1, b1, c1, a2, a3}));
  EXPECT_EQ(s.jobs.workers_started(), 5u);
}

// The chaos algorithms' artifacts through the real worker process:
// a message embedded, stored as PLY by the worker, extracted by a chained job
// and served as text; a wrong key fails the job with its message; an
// animation is served in the .frames format.
// Fair share while running: alice queues many jobs on the one worker, then
// bob submits one; bob's starts next, before alice's queue drains.
TEST(JobScheduler, ALateUserIsServedBeforeTheFirstUsersQueueDrains) {
  Scheduler s("jobs-fair-share", "sphere.off");
  StartOrder o(s.jobs);
  s.jobs.start();
  std::vector<std::string> alice;
  for (int k = 0; k < 6; ++k) alice.push_back(s.submit_sleep("alice", 0.2 + 0.001 * k));
  {
    // Bob comes once alice's first job runs.
    std::unique_lock lock(o.m);
    ASSERT_TRUE(o.cv.wait_for(lock, 30s, [&] { return !o.started.empty(); }));
  }
  const std::string bob = s.submit_sleep("bob", 0.01);
  std::unique_lock lock(o.m);
  ASSERT_TRUE(o.cv.wait_for(lock, 60s, [&] { return o.ended == 7; }));
  const auto at = std::find(o.started.begin(), o.started.end(), bob) - o.started.begin();
  // At most the job running when he came and the next one of alice's before his.
  EXPECT_LE(at, 2) << "bob's job started " << at << "th of 7";
  EXPECT_EQ(o.started.back(), alice.back());
}

TEST(JobsChaos, EmbedExtractAndAnimateThroughTheWorker) {
  Scheduler s("jobs-chaos", "elephant.off");
  JobScheduler& jobs = s.jobs;
  const MeshRecord& mesh = s.mesh;
  std::mutex m;
  std::condition_variable cv;
  std::set<std::string> ended;
  jobs.on_event = [&](const json& e, const Access&) {
    std::lock_guard lock(m);
    if (e["type"] == "job_done" || e["type"] == "job_failed") ended.insert(e["job"]["id"].get<std::string>());
    cv.notify_all();
  };
  jobs.start();
  auto run = [&](const json& request) {
    const std::string id = jobs.submit(request)["id"];
    std::unique_lock lock(m);
    EXPECT_TRUE(cv.wait_for(lock, 60s, [&] { return ended.contains(id); })) << request.dump();
    return *jobs.get(id);
  };

  const std::string message = "hidden in the elephant \xc3\xa9";
  const json embed = run({{"algorithm", "chaos_embed"},
                          {"inputs", {{"mesh", mesh.id}}},
                          {"params", {{"key", "k"}, {"message", message}}}});
  ASSERT_EQ(embed["state"], "done") << embed.dump();
  const json from = {{"job", embed["id"]}, {"artifact", "mesh"}};
  const json extract = run({{"algorithm", "chaos_extract"}, {"inputs", {{"mesh", from}}}, {"params", {{"key", "k"}}}});
  ASSERT_EQ(extract["state"], "done") << extract.dump();
  bool text = false;
  for (const auto& a : extract["artifacts"]) text |= a["name"] == "message" && a["kind"] == "text";
  EXPECT_TRUE(text) << extract.dump();
  EXPECT_EQ(jobs.artifact(extract["id"], "message", "txt").bytes, message);

  const json wrong = run({{"algorithm", "chaos_extract"}, {"inputs", {{"mesh", from}}}, {"params", {{"key", "K"}}}});
  EXPECT_EQ(wrong["state"], "failed");
  EXPECT_NE(wrong["error"].get<std::string>().find("no message found with this key"), std::string::npos)
      << wrong.dump();

  const json anim = run(
      {{"algorithm", "chaos_animate"}, {"inputs", {{"mesh", mesh.id}}}, {"params", {{"frames", 4}, {"map", "henon"}}}});
  ASSERT_EQ(anim["state"], "done") << anim.dump();
  const Animation a = decode_frames(jobs.artifact(anim["id"], "animation", "frames").bytes);
  EXPECT_EQ(a.frame_count(), 5u);
  EXPECT_EQ(a.base.num_vertices(), 2775u);
  EXPECT_EQ(a.base.num_faces(), 5558u);
}

}  // namespace
}  // namespace cgview::server
