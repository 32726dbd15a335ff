// The chaos algorithms' artifacts through the real worker process and the
// JobScheduler (issue 9): a message embedded, stored as PLY by the worker,
// extracted by a chained job and served as text; a wrong key fails the job
// with its message; an animation is served in the .frames format.
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>

#include "core/animation.h"
#include "jobs.h"
#include "mesh_service.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

TEST(JobsChaos, EmbedExtractAndAnimateThroughTheWorker) {
  const auto dir = test::temp_dir("jobs-chaos");
  Store store(dir);
  MeshService meshes(store);
  std::ifstream f(test::sample("elephant.off"), std::ios::binary);
  std::stringstream bytes;
  bytes << f.rdbuf();
  const MeshRecord mesh = meshes.upload("elephant.off", "", bytes.str());
  JobConfig config;
  config.worker = test::bin("cgview-worker-test");
  config.max_workers = 1;
  JobScheduler jobs(meshes, config);
  std::mutex m;
  std::condition_variable cv;
  std::set<std::string> ended;
  jobs.on_event = [&](const json& e) {
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
  EXPECT_NE(wrong["error"].get<std::string>().find("no message found with this key"), std::string::npos) << wrong.dump();

  const json anim = run({{"algorithm", "chaos_animate"},
                         {"inputs", {{"mesh", mesh.id}}},
                         {"params", {{"frames", 4}, {"map", "henon"}}}});
  ASSERT_EQ(anim["state"], "done") << anim.dump();
  const Animation a = decode_frames(jobs.artifact(anim["id"], "animation", "frames").bytes);
  EXPECT_EQ(a.frame_count(), 5u);
  EXPECT_EQ(a.base.num_vertices(), 2775u);
  EXPECT_EQ(a.base.num_faces(), 5558u);
}

}  // namespace
}  // namespace cgview::server
