// Quotas through the router (no sockets) with a job scheduler on the test
// worker: the config file (sections, overrides, errors naming the key), the
// storage quota (413 naming the limit and the use; stored data intact; other
// users unaffected), the concurrent job cap (429 with Retry-After), and
// GET /api/v1/me.  The real cgview-server refuses a bad config file.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "auth.h"
#include "config.h"
#include "config_error.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "router.h"
#include "router_harness.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

std::string sample_bytes(const std::string& name) { return test::read_bytes(test::sample(name)); }

TEST(QuotaConfig, SectionsAndOverrides) {
  ServerConfig c;
  apply_config(json::parse(R"({
    "server": {"port": 9000, "max_upload_mb": 16, "job_workers": 3, "auth": "required"},
    "limits": {"storage_mb": 500, "concurrent_jobs": 4},
    "users": {"alice": {"storage_mb": 0.5}, "bob": {"concurrent_jobs": null}, "root": {"concurrent_jobs": 8}}
  })"),
               c);
  EXPECT_EQ(c.port, 9000);
  EXPECT_EQ(c.max_upload_bytes, std::size_t(16) << 20);
  EXPECT_EQ(c.jobs.max_workers, 3);
  EXPECT_TRUE(c.auth_required);
  const QuotaConfig& q = c.jobs.quotas;
  // A user without an entry: the defaults.
  EXPECT_EQ(q.limits({"carol", false}).storage_bytes, std::uint64_t(500) << 20);
  EXPECT_EQ(q.limits({"carol", false}).concurrent_jobs, 4);
  // Each field given replaces the default; the others stay.
  EXPECT_EQ(q.limits({"alice", false}).storage_bytes, std::uint64_t(1) << 19);
  EXPECT_EQ(q.limits({"alice", false}).concurrent_jobs, 4);
  // null: unlimited.
  EXPECT_EQ(q.limits({"bob", false}).concurrent_jobs, std::nullopt);
  EXPECT_EQ(q.limits({"bob", false}).storage_bytes, std::uint64_t(500) << 20);
  // Admins and the local user: unlimited unless named.
  EXPECT_EQ(q.limits({"admin2", true}).storage_bytes, std::nullopt);
  EXPECT_EQ(q.limits(Caller::local()).concurrent_jobs, std::nullopt);
  EXPECT_EQ(q.limits({"root", true}).concurrent_jobs, 8);
  EXPECT_EQ(q.limits({"root", true}).storage_bytes, std::nullopt);
}

// The hardening limits are keys of the server section too, named after their flags.
TEST(QuotaConfig, HardeningLimitsInTheServerSection) {
  ServerConfig c;
  apply_config(json::parse(R"({"server": {"max_header_kb": 16, "max_ws_message_kb": 256, "request_timeout_s": 10,
    "min_body_rate_kb": 32, "idle_timeout_s": 20, "ws_idle_timeout_s": 40, "max_connections_per_ip": 8,
    "rate_limit": {"rate": 5}, "tls_cert": "c.pem", "tls_key": "k.pem"}})"),
               c);
  EXPECT_EQ(c.max_header_bytes, std::size_t(16) << 10);
  EXPECT_EQ(c.max_ws_message_bytes, std::size_t(256) << 10);
  EXPECT_EQ(c.request_timeout_s, 10);
  EXPECT_EQ(c.min_body_rate, 32 * 1024);
  EXPECT_EQ(c.idle_timeout_s, 20);
  EXPECT_EQ(c.ws_idle_timeout_s, 40);
  EXPECT_EQ(c.max_connections_per_ip, 8);
  EXPECT_EQ(c.rate_per_s, 5);
  EXPECT_EQ(c.rate_burst, 20) << "as --rate-limit 5: a burst of four seconds";
  EXPECT_EQ(c.tls_cert, "c.pem");
  EXPECT_NE(config_error({{"server", {{"rate_limit", {{"rate", 5}, {"burst", 0}}}}}}).find("server.rate_limit.burst"),
            std::string::npos);
  EXPECT_NE(config_error({{"server", {{"rate_limit", {{"per_s", 5}}}}}}).find("unknown key"), std::string::npos);
}

TEST(QuotaConfig, ErrorsNameTheKey) {
  EXPECT_NE(config_error({{"limits", {{"storage_bytes", 5}}}}).find("limits.storage_bytes: unknown key"),
            std::string::npos);
  EXPECT_NE(config_error({{"server", {{"wrokers", 2}}}}).find("server.wrokers: unknown key"), std::string::npos);
  EXPECT_NE(config_error({{"users", {{"alice", {{"jobs", 2}}}}}}).find("users.alice.jobs: unknown key"),
            std::string::npos);
  EXPECT_NE(config_error({{"limit", json::object()}}).find("limit: unknown key"), std::string::npos);
  EXPECT_NE(config_error({{"limits", {{"storage_mb", -1}}}}).find("limits.storage_mb: must be"), std::string::npos);
  EXPECT_NE(config_error({{"limits", {{"concurrent_jobs", 1.5}}}}).find("limits.concurrent_jobs: must be an integer"),
            std::string::npos);
  EXPECT_NE(config_error({{"users", {{"no one", json::object()}}}}).find("is not a user name"), std::string::npos);
  EXPECT_NE(config_error({{"server", {{"port", "80"}}}}).find("server.port: must be an integer"), std::string::npos);
  EXPECT_EQ(config_error(json::object()), "");
}

TEST(QuotaConfig, TheServerRefusesABadFileNamingTheKey) {
  const auto dir = test::temp_dir("quota-bad-config");
  const auto file = dir / "bad.json";
  std::ofstream(file) << R"({"limits": {"storage_mb": 10, "concurent_jobs": 2}})";
  const std::string cmd = test::bin("cgview-server") + " --port 0 --samples none --data-dir '" +
                          (dir / "data").string() + "' --config '" + file.string() + "' 2>&1";
  FILE* p = ::popen(cmd.c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[512];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  const int status = ::pclose(p);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("limits.concurent_jobs: unknown key"), std::string::npos) << out;
  EXPECT_NE(out.find("bad.json"), std::string::npos) << out;
  // Not JSON: the file is named.
  std::ofstream(file) << "{limits";
  p = ::popen(cmd.c_str(), "r");
  out.clear();
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  EXPECT_NE(::pclose(p), 0);
  EXPECT_NE(out.find("bad.json: not JSON"), std::string::npos) << out;
  // Without --config, DATA-DIR/config.json is read when it is there.
  std::filesystem::create_directories(dir / "data");
  std::ofstream(dir / "data" / "config.json") << R"({"users": {"alice": {"storage": 1}}})";
  p = ::popen(
      (test::bin("cgview-server") + " --port 0 --samples none --data-dir '" + (dir / "data").string() + "' 2>&1")
          .c_str(),
      "r");
  out.clear();
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, p)) > 0;) out.append(buf, n);
  EXPECT_NE(::pclose(p), 0);
  EXPECT_NE(out.find("config.json: users.alice.storage: unknown key"), std::string::npos) << out;
}

class QuotaTest : public test::RouterFixture {
 protected:
  void start(const json& config_doc) {
    make_dir("quota-");
    ServerConfig sc;
    apply_config(config_doc, sc);
    JobConfig jc = sc.jobs;
    jc.max_workers = 4;  // alice's two long jobs leave room for bob's
    open_with_users(dir_, jc);
  }

  HttpResponse call(const std::string& token, const std::string& method, const std::string& target,
                    std::string body = "") {
    return router_->handle({method, target, std::move(body), "Bearer " + token});
  }
  HttpResponse upload(const std::string& token, const std::string& sample, const std::string& as = "") {
    return call(token, "POST", "/api/v1/meshes?name=" + (as.empty() ? sample : as), sample_bytes(sample));
  }
  json me(const std::string& token) { return json::parse(call(token, "GET", "/api/v1/me").body); }
  HttpResponse sleep_job(const std::string& token, const std::string& mesh, double seconds) {
    return call(
        token, "POST", "/api/v1/jobs",
        json{{"algorithm", "test_sleep"}, {"inputs", {{"mesh", mesh}}}, {"params", {{"seconds", seconds}}}}.dump());
  }
  json wait_job(const std::string& token, const std::string& id) {
    for (auto until = std::chrono::steady_clock::now() + 60s; std::chrono::steady_clock::now() < until;) {
      const json j = json::parse(call(token, "GET", "/api/v1/jobs/" + id).body);
      const std::string state = j.value("state", "");
      if (state == "done" || state == "failed" || state == "cancelled") return j;
      std::this_thread::sleep_for(20ms);
    }
    ADD_FAILURE() << "job " << id << " did not end";
    return {};
  }
};

TEST_F(QuotaTest, AnUploadOverTheStorageQuotaIs413NamingTheLimitAndTheUse) {
  const std::string sphere = sample_bytes("sphere.off");  // 7816 bytes
  // Room for one sphere and a bit: 10 KB.
  start({{"limits", {{"storage_mb", 10.0 / 1024}}}, {"users", {{"bob", {{"storage_mb", 1}}}}}});
  const HttpResponse first = upload(alice_, "sphere.off");
  ASSERT_EQ(first.status, 201) << first.body;
  const std::string id = json::parse(first.body)["id"];
  json m = me(alice_);
  EXPECT_EQ(m["user"], "alice");
  EXPECT_EQ(m["storage_bytes_used"], sphere.size());
  EXPECT_EQ(m["storage_bytes_limit"], 10240);

  const HttpResponse over = upload(alice_, "sphere.off", "again.off");
  EXPECT_EQ(over.status, 413) << over.body;
  const json e = json::parse(over.body);
  EXPECT_EQ(e["error"], "storage_quota");
  EXPECT_EQ(e["detail"], "storage quota of 10.0 KB exceeded: 7.6 KB used, this upload is 7.6 KB");
  EXPECT_EQ(e["limit"], 10240);
  EXPECT_EQ(e["used"], sphere.size());

  // What alice had is intact; nothing more was stored.
  const json list = json::parse(call(alice_, "GET", "/api/v1/meshes").body)["meshes"];
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0]["id"], id);
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes/" + id + "/download").body, sphere);
  EXPECT_EQ(me(alice_)["storage_bytes_used"], sphere.size());
  // A smaller file still fits.
  EXPECT_EQ(upload(alice_, "cube.off").status, 201);

  // Bob has his own quota (1 MB) and his own use.
  EXPECT_EQ(upload(bob_, "sphere.off").status, 201);
  EXPECT_EQ(upload(bob_, "sphere.off", "b.off").status, 201);
  EXPECT_EQ(me(bob_)["storage_bytes_used"], 2 * sphere.size());
  EXPECT_EQ(me(bob_)["storage_bytes_limit"], 1 << 20);

  // Deleting frees the room.
  EXPECT_EQ(call(alice_, "DELETE", "/api/v1/meshes/" + id).status, 204);
  EXPECT_EQ(upload(alice_, "sphere.off", "again.off").status, 201);
}

TEST_F(QuotaTest, JobArtifactsCountAreHeldToTheQuotaAndAFullQuotaRefusesJobs) {
  // Bob's quota is one sphere exactly (7816 bytes).
  start({{"limits", {{"storage_mb", 8.5 / 1024}}}, {"users", {{"bob", {{"storage_mb", 7816.0 / (1 << 20)}}}}}});
  const HttpResponse up = upload(alice_, "sphere.off");
  ASSERT_EQ(up.status, 201);
  const std::string mesh = json::parse(up.body)["id"];
  const std::uint64_t mesh_bytes = me(alice_)["storage_bytes_used"];
  // The job's result (a scalar field per vertex of the sphere, 648 bytes,
  // and its list) does not fit in the 888 bytes left: the job fails saying
  // so, and keeps nothing.
  const HttpResponse job = sleep_job(alice_, mesh, 0.01);
  ASSERT_EQ(job.status, 201) << job.body;
  const json failed = wait_job(alice_, json::parse(job.body)["id"]);
  EXPECT_EQ(failed["state"], "failed");
  EXPECT_NE(
      failed.value("error", json("")).get<std::string>().find("bytes its owner has left under their storage quota"),
      std::string::npos)
      << failed.dump();
  EXPECT_EQ(me(alice_)["storage_bytes_used"], mesh_bytes);
  // On a smaller mesh the result fits, and counts.
  const std::string cube = json::parse(upload(alice_, "cube.off").body)["id"];
  const std::uint64_t meshes = me(alice_)["storage_bytes_used"];
  const HttpResponse fits = sleep_job(alice_, cube, 0.01);
  ASSERT_EQ(fits.status, 201) << fits.body;
  EXPECT_EQ(wait_job(alice_, json::parse(fits.body)["id"])["state"], "done");
  const std::uint64_t used = me(alice_)["storage_bytes_used"];
  EXPECT_GT(used, meshes);
  EXPECT_LE(used, 8704u);
  // No room at all for results: 413 at submit, naming the limit and the use.
  const HttpResponse bobs = upload(bob_, "sphere.off");
  ASSERT_EQ(bobs.status, 201) << bobs.body;
  const HttpResponse refused = sleep_job(bob_, json::parse(bobs.body)["id"], 0.02);
  EXPECT_EQ(refused.status, 413) << refused.body;
  const json e = json::parse(refused.body);
  EXPECT_EQ(e["error"], "storage_quota");
  EXPECT_NE(e["detail"].get<std::string>().find("storage quota of 7.6 KB exceeded: "), std::string::npos) << e;
  EXPECT_NE(e["detail"].get<std::string>().find("no room is left for a job's results"), std::string::npos) << e;
  EXPECT_EQ(e["used"], 7816);
  // Alice is not affected.
  EXPECT_EQ(sleep_job(alice_, cube, 0.02).status, 201);
}

TEST_F(QuotaTest, OverTheJobCapIs429WithRetryAfter) {
  start({{"limits", {{"concurrent_jobs", 2}}}, {"users", {{"bob", {{"concurrent_jobs", 1}}}}}});
  const std::string mesh = json::parse(upload(alice_, "cube.off").body)["id"];
  const HttpResponse a1 = sleep_job(alice_, mesh, 30), a2 = sleep_job(alice_, mesh, 31);
  ASSERT_EQ(a1.status, 201) << a1.body;
  ASSERT_EQ(a2.status, 201) << a2.body;
  EXPECT_EQ(me(alice_)["jobs_active"], 2);
  EXPECT_EQ(me(alice_)["jobs_limit"], 2);
  const HttpResponse over = sleep_job(alice_, mesh, 0.01);
  EXPECT_EQ(over.status, 429) << over.body;
  const json e = json::parse(over.body);
  EXPECT_EQ(e["error"], "job_limit");
  EXPECT_EQ(e["detail"], "concurrent job limit of 2 reached: 2 queued or running; submit again when one ends");
  bool retry_after = false;
  for (const auto& [name, value] : over.headers) retry_after |= name == "Retry-After" && std::stoi(value) > 0;
  EXPECT_TRUE(retry_after);
  // Nothing was queued for it.
  EXPECT_EQ(json::parse(call(alice_, "GET", "/api/v1/jobs").body)["jobs"].size(), 2u);

  // Bob's cap is his own (1), and alice's jobs do not count against it.  (Another
  // mesh than alice's: results are cached by content, across users.)
  const std::string bob_mesh = json::parse(upload(bob_, "tetrahedron.off").body)["id"];
  const HttpResponse b1 = sleep_job(bob_, bob_mesh, 0.01);
  ASSERT_EQ(b1.status, 201) << b1.body;
  EXPECT_EQ(wait_job(bob_, json::parse(b1.body)["id"])["state"], "done");
  // A cached result runs nothing: it does not count, and is answered even at the cap.
  const HttpResponse b2 = sleep_job(bob_, bob_mesh, 30);
  ASSERT_EQ(b2.status, 201);
  EXPECT_EQ(sleep_job(bob_, bob_mesh, 0.02).status, 429);
  const HttpResponse cached = sleep_job(bob_, bob_mesh, 0.01);
  EXPECT_EQ(cached.status, 201) << cached.body;
  EXPECT_EQ(json::parse(cached.body)["state"], "done");

  // When one of alice's ends (cancelled here), she may submit again.
  EXPECT_EQ(call(alice_, "DELETE", "/api/v1/jobs/" + json::parse(a1.body)["id"].get<std::string>()).status, 200);
  EXPECT_EQ(sleep_job(alice_, mesh, 0.01).status, 201);
  call(alice_, "DELETE", "/api/v1/jobs/" + json::parse(a2.body)["id"].get<std::string>());
  call(bob_, "DELETE", "/api/v1/jobs/" + json::parse(b2.body)["id"].get<std::string>());
}

TEST_F(QuotaTest, NoLimitsByDefault) {
  start(json::object());
  EXPECT_EQ(upload(alice_, "sphere.off").status, 201);
  const json m = me(alice_);
  EXPECT_EQ(m["storage_bytes_limit"], nullptr);
  EXPECT_EQ(m["jobs_limit"], nullptr);
  EXPECT_EQ(m["admin"], false);
  EXPECT_EQ(m["jobs_active"], 0);
}

}  // namespace
}  // namespace cgview::server
