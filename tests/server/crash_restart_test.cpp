// SIGKILL at the worst moments: during uploads, while a job's worker is
// writing its artifacts, and during the store's migration.  After a restart
// nothing half-written is visible: every mesh listed downloads whole, no
// blob lacks its record nor a record its blob, no job is done with a cut
// artifact, and SQLite's integrity_check is ok.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <string>
#include <thread>

#include "server_harness.h"
#include "sqlite_query.h"
#include "test_support.h"

extern char** environ;

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

class CrashRestart : public ServerFixture {
 protected:
  CrashRestart() : ServerFixture("crash-restart-") {}

  json meshes() { return http_get(port(), "/api/v1/meshes").body_json()["meshes"]; }
  json job(const std::string& id) { return http_get(port(), "/api/v1/jobs/" + id).body_json(); }
  json wait_end(const std::string& id) { return wait_job_end(port(), id, 30s); }

  // The store as a user and an admin see it: every mesh listed downloads as
  // `bytes`, the blobs are exactly the listed meshes' files, no upload is
  // left in tmp, and the database is sound.
  void expect_whole_store(const std::string& bytes) {
    std::set<std::string> ids;
    for (const json& m : meshes()) {
      const std::string id = m["id"];
      ids.insert(id);
      EXPECT_TRUE(http_get(port(), "/api/v1/meshes/" + id + "/download").body == bytes) << "mesh " << id;
    }
    for (const auto& e : fs::directory_iterator(data_ / "blobs")) {
      const std::string name = e.path().filename().string();
      EXPECT_TRUE(ids.count(name.substr(0, name.find('.')))) << "a blob no record names: " << name;
    }
    for (const std::string& id : ids) EXPECT_TRUE(fs::exists(data_ / "blobs" / (id + ".off"))) << id;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(data_ / "tmp", ec))
      EXPECT_FALSE(e.path().filename().string().starts_with("upload-")) << e.path();
    EXPECT_EQ(integrity_check(data_ / "cgview.db"), "ok");
  }
};

TEST_F(CrashRestart, UploadsKilledAtRandomMomentsLeaveOnlyWholeMeshes) {
  const std::string bytes = read_bytes(sample("armadillo.off"));
  std::mt19937 rng(20261125);
  std::size_t answered = 0;
  for (int round = 0; round < 8; ++round) {
    ASSERT_TRUE(server_.start(data_, {}, dir_));
    const unsigned short p = server_.port();
    std::atomic<bool> stop{false};
    std::atomic<std::size_t> ok{0};
    // Two clients, so that one upload is being read while another is stored.
    auto upload_loop = [&] {
      while (!stop)
        if (http_call(p, Method::post, "/api/v1/meshes?name=armadillo.off", bytes, 5s).status == 201) ++ok;
    };
    std::thread a(upload_loop), b(upload_loop);
    std::this_thread::sleep_for(std::chrono::milliseconds(60 + rng() % 240));
    EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
    stop = true;
    a.join();
    b.join();
    answered += ok;
  }
  ASSERT_TRUE(server_.start(data_, {}, dir_));
  // Every upload answered 201 is there; some killed before their answer may be too, whole.
  EXPECT_GE(meshes().size(), answered);
  expect_whole_store(bytes);
}

TEST_F(CrashRestart, AServerKilledWhileAWorkerWritesItsArtifactsNeverShowsThemHalfWritten) {
  // A worker that writes its results, then cuts its field's file in half and
  // waits: the server is killed with the artifact half-written on disk.
  const fs::path script = dir_ / "half-writing-worker";
  fs::create_directories(dir_);
  const std::string worker = bin("cgview-worker-test");
  write_text(script, "#!/bin/sh\n[ \"$1\" = --list ] && exec " + worker + " --list\n" + worker +
                         " \"$@\"\nd=" + std::string(kWorkerOutSh) +
                         "\nfor f in \"$d\"/*.f32; do truncate -s \"$(( $(stat -c %s \"$f\") / "
                         "2 ))\" \"$f\"; done\ntouch \"$d/half-written\"\nexec sleep 30\n");
  ::chmod(script.c_str(), 0755);
  ASSERT_TRUE(server_.start(data_, {"--worker", script.string()}, dir_));
  const HttpResult up =
      http_call(port(), Method::post, "/api/v1/meshes?name=sphere.off", read_bytes(sample("sphere.off")));
  ASSERT_EQ(up.status, 201) << up.body;
  const json mesh = up.body_json();
  const json body = {
      {"algorithm", "centroid_distance"}, {"inputs", {{"mesh", mesh["id"]}}}, {"params", {{"exponent", 1.25}}}};
  const HttpResult s = http_call(port(), Method::post, "/api/v1/jobs", body.dump());
  ASSERT_EQ(s.status, 201) << s.body;
  const std::string id = s.body_json()["id"];
  // The worker writes in its run's own directory (runs/ID/work), never where results are served from.
  const fs::path half = data_ / "runs" / id / "work" / "half-written";
  for (int i = 0; i < 400 && !fs::exists(half); ++i) std::this_thread::sleep_for(25ms);
  ASSERT_TRUE(fs::exists(half));
  EXPECT_EQ(job(id)["state"], "running");
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);

  // Started again with a worker that is whole: the job runs again, and only its whole result is seen.
  ASSERT_TRUE(server_.start(data_, {"--worker", worker}, dir_));
  const json j = wait_end(id);
  ASSERT_EQ(j["state"], "done") << j.dump();
  const std::size_t vertices = mesh["report"]["vertices"];
  EXPECT_EQ(j["artifacts"][0]["count"], vertices);
  const HttpResult f32 = http_get(port(), "/api/v1/jobs/" + id + "/artifacts/distance?format=f32");
  EXPECT_EQ(f32.body.size(), vertices * sizeof(float));
  EXPECT_FALSE(fs::exists(half)) << "the killed run's files were cleared";
  EXPECT_FALSE(fs::exists(data_ / "jobs" / id / "half-written"));
  EXPECT_EQ(integrity_check(data_ / "cgview.db"), "ok");
}

TEST_F(CrashRestart, AMigrationKilledPartWayLeavesTheStoreWholeAndIsDoneAtTheNextStart) {
  // A store as an older server left it: a mesh and a done job, without the
  // columns this server adds when it opens the store.
  const std::string bytes = read_bytes(sample("sphere.off"));
  ASSERT_TRUE(server_.start(data_, {"--worker", bin("cgview-worker-test")}, dir_));
  const HttpResult up = http_call(port(), Method::post, "/api/v1/meshes?name=sphere.off", bytes);
  ASSERT_EQ(up.status, 201) << up.body;
  const json body = {{"algorithm", "centroid_distance"},
                     {"inputs", {{"mesh", up.body_json()["id"]}}},
                     {"params", {{"exponent", 1.75}}}};
  const std::string id = http_call(port(), Method::post, "/api/v1/jobs", body.dump()).body_json()["id"];
  ASSERT_EQ(wait_end(id)["state"], "done");
  const std::string field = http_get(port(), "/api/v1/jobs/" + id + "/artifacts/distance?format=f32").body;
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  const fs::path db = data_ / "cgview.db";
  for (const char* drop : {"ALTER TABLE jobs DROP COLUMN warnings", "ALTER TABLE jobs DROP COLUMN worker_token",
                           "ALTER TABLE meshes DROP COLUMN material"})
    ASSERT_EQ(sqlite_query(db, drop), "") << drop;

  // The server started and killed at once, again and again: some of these
  // kills land while it adds the columns.
  const std::string server = bin("cgview-server");
  std::mt19937 rng(7);
  for (int round = 0; round < 10; ++round) {
    std::vector<std::string> args = {server,       "--host",       "127.0.0.1", "--port", "0",
                                     "--data-dir", data_.string(), "--samples", "none"};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t quiet;
    posix_spawn_file_actions_init(&quiet);
    posix_spawn_file_actions_addopen(&quiet, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&quiet, 2, "/dev/null", O_WRONLY, 0);
    pid_t pid = -1;
    ASSERT_EQ(posix_spawn(&pid, server.c_str(), &quiet, nullptr, argv.data(), environ), 0);
    posix_spawn_file_actions_destroy(&quiet);
    std::this_thread::sleep_for(std::chrono::microseconds(rng() % 40000));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_EQ(integrity_check(db), "ok") << "after a kill in round " << round;
  }

  ASSERT_TRUE(server_.start(data_, {"--worker", bin("cgview-worker-test")}, dir_));
  expect_whole_store(bytes);
  const json j = job(id);
  EXPECT_EQ(j["state"], "done") << j.dump();
  EXPECT_EQ(j["warnings"], json::array());
  EXPECT_EQ(http_get(port(), "/api/v1/jobs/" + id + "/artifacts/distance?format=f32").body, field);
  EXPECT_EQ(sqlite_query(db, "SELECT COUNT(*) FROM pragma_table_info('jobs') WHERE name = 'warnings'"), "1");
  EXPECT_EQ(sqlite_query(db, "SELECT material FROM meshes"), "{}");
}

}  // namespace
}  // namespace cgview::test
