// A full disk on the real server: its data directory on a tmpfs of its own
// (a mount namespace of this test process, which the server inherits).
// Uploads answer 507 with a JSON error, a job whose results find no room
// fails saying so, nothing stored is damaged (every mesh downloads as
// uploaded, SQLite's integrity_check is ok, no blob without its record), and
// once space is freed the server stores again.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include <sched.h>
#include <sys/mount.h>

#include "server_harness.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

class DiskFull : public ServerFixture {
 protected:
  DiskFull() : ServerFixture("disk-full-") {}
  void TearDown() override {
    server_.kill_now();
    ::umount2(data_.c_str(), MNT_DETACH);
    ServerFixture::TearDown();
  }

  // data_ becomes a tmpfs of `mb` MB seen by this process and its children only.
  bool small_disk(int mb) {
    fs::create_directories(data_);
    if (::unshare(CLONE_NEWNS) != 0) return false;
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0) return false;
    const std::string opts = "size=" + std::to_string(mb) + "m";
    return ::mount("tmpfs", data_.c_str(), "tmpfs", 0, opts.c_str()) == 0;
  }

  HttpResult upload(const std::string& bytes) {
    return http_call(port(), Method::post, "/api/v1/meshes?name=elephant.off", bytes, 30s);
  }

  // Fills what is left of the disk with one file; its path.
  fs::path fill() {
    const fs::path p = data_ / "filler";
    std::ofstream f(p, std::ios::binary);
    const std::string block(1 << 16, 'x');
    while (f.write(block.data(), std::streamsize(block.size()))) {
    }
    return p;
  }
};

TEST_F(DiskFull, UploadsAre507JobsFailSayingSoNothingStoredIsDamagedAndFreedSpaceServes) {
  if (!small_disk(4))
    GTEST_SKIP() << "cannot mount a tmpfs here (needs root: unshare, mount): " << std::strerror(errno);
  ASSERT_TRUE(server_.start(data_, {}, dir_));
  const std::string bytes = read_bytes(sample("elephant.off"));  // 170 kB
  std::vector<std::string> ids;
  HttpResult full;
  for (int i = 0; i < 60; ++i) {
    const HttpResult r = upload(bytes);
    if (r.status != 201) {
      full = r;
      break;
    }
    ids.push_back(r.body_json()["id"]);
  }
  ASSERT_FALSE(ids.empty());
  expect_error(full, 507, "insufficient_storage");
  EXPECT_NE(full.body_json().value("detail", "").find("storage is full"), std::string::npos) << full.body;
  expect_healthy();
  // Every disk byte taken: a job's results find no room.
  const fs::path filler = fill();
  expect_error(upload(bytes), 507, "insufficient_storage");
  // The job's record may find no room (507 at once, SQLite full), or the
  // record fits in SQLite's last free page and the job fails when its files do not.
  const HttpResult sub = http_call(port(), Method::post, "/api/v1/jobs",
                                   json{{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", ids[0]}}}}.dump());
  if (sub.status == 507) {
    expect_error(sub, 507, "insufficient_storage");
  } else {
    ASSERT_EQ(sub.status, 201u) << sub.body;
    json job;
    for (int i = 0; i < 500; ++i) {
      job = http_get(port(), "/api/v1/jobs/" + sub.body_json()["id"].get<std::string>()).body_json();
      if (job.value("state", "") == "failed" || job.value("state", "") == "done") break;
      std::this_thread::sleep_for(20ms);
    }
    EXPECT_EQ(job.value("state", ""), "failed") << job.dump();
    EXPECT_NE(job.value("error", "").find("storage is full"), std::string::npos) << job.dump();
  }
  expect_healthy();

  // Nothing stored is damaged: every mesh listed downloads as it was uploaded.
  const json list = http_get(port(), "/api/v1/meshes").body_json();
  ASSERT_EQ(list["meshes"].size(), ids.size());
  for (const auto& id : ids) EXPECT_EQ(http_get(port(), "/api/v1/meshes/" + id + "/download").body, bytes) << id;
  // The store: integrity_check ok, one blob a record and no half-written file.
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open_v2((data_ / "cgview.db").c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  ASSERT_EQ(sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &s, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_step(s), SQLITE_ROW);
  EXPECT_STREQ(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)), "ok");
  sqlite3_finalize(s);
  sqlite3_close(db);
  std::set<std::string> blobs;
  for (const auto& e : fs::directory_iterator(data_ / "blobs")) blobs.insert(e.path().filename().string());
  std::set<std::string> want;
  for (const auto& id : ids) want.insert(id + ".off");
  EXPECT_EQ(blobs, want);
  std::size_t left = 0;
  for (const auto& e : fs::directory_iterator(data_ / "tmp"))
    left += e.path().filename().string().starts_with("upload-");
  EXPECT_EQ(left, 0u);

  // Space freed: stored again.
  fs::remove(filler);
  const HttpResult del = http_call(port(), Method::delete_, "/api/v1/meshes/" + ids.back());
  EXPECT_EQ(del.status, 204u) << del.body;
  const HttpResult again = upload(bytes);
  EXPECT_EQ(again.status, 201u) << again.body;
  expect_healthy();
}

}  // namespace
}  // namespace cgview::test
