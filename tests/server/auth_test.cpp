// Users, tokens and isolation through the router (no sockets), with a job
// scheduler on the test worker: user A sees, reads, renders, deletes and
// uses as a job input nothing of user B's, over every route of the OpenAPI
// document (a new route is covered without editing this file); sharing;
// revoked tokens stop working at once; tokens are stored hashed.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "auth.h"
#include "core/errors.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "router_harness.h"
#include "router.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

using nlohmann::json;
using namespace std::chrono_literals;

class AuthTest : public test::RouterFixture {
 protected:
  void SetUp() override {
    make_dir("auth-");
    JobConfig jc;
    jc.max_workers = 2;
    open_with_users(dir_, jc);
    admin_ = Auth(*store_, true).add_user("root", true);
  }

  HttpResponse call(const std::string& token, const std::string& method, const std::string& target,
                    std::string body = "") {
    return router_->handle({method, target, std::move(body), token.empty() ? "" : "Bearer " + token});
  }

  std::string upload(const std::string& token, const std::string& sample = "cube.off") {
    const HttpResponse r = call(token, "POST", "/api/v1/meshes?name=" + sample, test::read_bytes(test::sample(sample)));
    EXPECT_EQ(r.status, 201) << r.body;
    return json::parse(r.body).value("id", "");
  }

  // Submits a job and waits for it to end; its id.
  std::string run_job(const std::string& token, const json& request) {
    const HttpResponse r = call(token, "POST", "/api/v1/jobs", request.dump());
    EXPECT_EQ(r.status, 201) << r.body;
    const std::string id = json::parse(r.body).value("id", "");
    for (auto until = std::chrono::steady_clock::now() + 60s; std::chrono::steady_clock::now() < until;) {
      const json j = json::parse(call(token, "GET", "/api/v1/jobs/" + id).body);
      if (j.value("state", "") == "done") return id;
      EXPECT_NE(j.value("state", ""), "failed") << j.dump();
      std::this_thread::sleep_for(20ms);
    }
    ADD_FAILURE() << "job " << id << " did not end";
    return id;
  }

  std::string admin_;
};

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size()))
    s.replace(p, from.size(), to);
  return s;
}

TEST_F(AuthTest, EveryApiRouteNeedsAToken) {
  for (const auto& r : router_->routes()) {
    SCOPED_TRACE(r.method + " " + r.pattern);
    const std::string target = std::regex_replace(r.pattern, std::regex(R"(\{[a-z_]+\})"), "x");
    for (const std::string& token :
         {std::string(), std::string("cgv_0123456789abcdef_") + std::string(64, '0'), std::string("not a token")}) {
      const HttpResponse res = call(token, r.method, target, "{}");
      EXPECT_EQ(res.status, 401) << res.body;
      EXPECT_EQ(json::parse(res.body).value("error", ""), "unauthorized");
    }
  }
  // The viewer's own files are public: it asks for the token.
  EXPECT_NE(call("", "GET", "/index.html").status, 401);
}

// A's view of every route with B's ids in it is the view of ids that do not
// exist; lists hold nothing of B's; B's data is untouched afterwards.
TEST_F(AuthTest, AUserSeesNothingOfAnothersOverEveryRoute) {
  const std::string b_mesh = upload(bob_);
  const std::string b_job = run_job(bob_, {{"algorithm", "test_translate"}, {"inputs", {{"mesh", b_mesh}}}});
  const std::string b_field =
      run_job(bob_, {{"algorithm", "test_sleep"}, {"inputs", {{"mesh", b_mesh}}}, {"params", {{"seconds", 0.0}}}});
  const std::string a_mesh = upload(alice_);
  // B teaches a course (with A's id of a member in it, a route's {user}).
  store_->add_user("bob", false, true);
  const HttpResponse course = call(bob_, "POST", "/api/v1/courses", json{{"title", "B's"}}.dump());
  ASSERT_EQ(course.status, 201) << course.body;
  const std::string b_course = json::parse(course.body).value("id", "");
  const std::map<std::string, std::pair<std::string, std::string>> values = {
      // placeholder: B's value, a value that does not exist
      {"name", {"mesh", "mesh"}},
      {"n", {"0", "0"}},
      {"user", {"bob", "nobody"}},
      {"which", {"result.png", "result.png"}}};
  const std::string fake_mesh = "00000000deadbeef", fake_job = "00000000feedface";
  // POST bodies that try to reach B's data: by id, as a job input, by sharing.
  auto body_for = [](const std::string& pattern, const std::string& mesh) {
    if (pattern == "/api/v1/jobs") return json{{"algorithm", "test_translate"}, {"inputs", {{"mesh", mesh}}}}.dump();
    return json{{"users", {"alice"}}}.dump();
  };
  int checked = 0;
  for (const auto& r : router_->routes()) {
    if (!r.pattern.starts_with("/api/")) continue;
    SCOPED_TRACE(r.method + " " + r.pattern);
    std::string b_target = r.pattern, fake_target = r.pattern;
    const bool jobs = r.pattern.starts_with("/api/v1/jobs");
    for (std::smatch m; std::regex_search(b_target, m, std::regex(R"(\{([a-z_]+)\})"));) {
      const std::string placeholder = m[0], name = m[1];
      std::string b, fake;
      if (name == "id" && r.pattern.starts_with("/api/v1/courses/")) {
        b = b_course, fake = fake_mesh;
      } else if (name == "id" &&
                 (r.pattern.starts_with("/api/v1/assignments/") || r.pattern.starts_with("/api/v1/submissions/"))) {
        b = fake = fake_job;  // B's would need a built plugin: an unknown one answers for it
      } else if (name == "id") {
        b = jobs ? b_job : b_mesh;
        fake = jobs ? fake_job : fake_mesh;
      } else if (values.count(name)) {
        std::tie(b, fake) = values.at(name);
      } else {
        FAIL() << "no value for {" << name << "}: add one to this test";
      }
      b_target = replace_all(b_target, placeholder, b);
      fake_target = replace_all(fake_target, placeholder, fake);
    }
    const HttpResponse as_a = call(alice_, r.method, b_target, body_for(r.pattern, b_mesh));
    const bool names_b = b_target != r.pattern || (r.method == "POST" && r.pattern == "/api/v1/jobs");
    if (!names_b) {  // a list, an upload, or no data at all: nothing of B's
      EXPECT_EQ(as_a.body.find(b_mesh), std::string::npos) << as_a.body;
      EXPECT_EQ(as_a.body.find(b_job), std::string::npos) << as_a.body;
    } else {
      // Another user's id answers exactly as an unknown one: 404, or 401 on
      // a job worker's routes, which take that job's token and no user's.
      const HttpResponse unknown = call(alice_, r.method, fake_target, body_for(r.pattern, fake_mesh));
      EXPECT_EQ(as_a.status, r.pattern.starts_with("/api/v1/worker/") ? 401 : 404) << as_a.body;
      EXPECT_EQ(unknown.status, as_a.status);
      EXPECT_EQ(
          replace_all(replace_all(replace_all(as_a.body, b_mesh, fake_mesh), b_job, fake_job), b_course, fake_mesh),
          unknown.body);
      ++checked;
    }
  }
  EXPECT_GE(checked, 9);
  // B's earlier job as A's input, and B's field on A's render.
  const HttpResponse chained = call(
      alice_, "POST", "/api/v1/jobs",
      json{{"algorithm", "test_translate"}, {"inputs", {{"mesh", {{"job", b_job}, {"artifact", "mesh"}}}}}}.dump());
  EXPECT_EQ(chained.status, 404) << chained.body;
  const HttpResponse field =
      call(alice_, "GET", "/api/v1/meshes/" + a_mesh + "/render.png?field=" + b_field + "/index");
  EXPECT_EQ(field.status, 400) << field.body;
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes/" + a_mesh + "/render.png?field=index").status, 400);
  // Health counts A's meshes only.
  EXPECT_EQ(json::parse(call(alice_, "GET", "/api/v1/health").body)["meshes"], 1);
  // B's data is all there; the admin sees both users'.
  EXPECT_EQ(call(bob_, "GET", "/api/v1/meshes/" + b_mesh).status, 200);
  EXPECT_EQ(json::parse(call(bob_, "GET", "/api/v1/jobs/" + b_job).body)["state"], "done");
  EXPECT_EQ(call(bob_, "GET", "/api/v1/jobs/" + b_job + "/artifacts/mesh").status, 200);
  const std::string all = call(admin_, "GET", "/api/v1/meshes").body;
  EXPECT_NE(all.find(b_mesh), std::string::npos);
  EXPECT_NE(all.find(a_mesh), std::string::npos);
  EXPECT_NE(call(admin_, "GET", "/api/v1/jobs").body.find(b_job), std::string::npos);
}

TEST_F(AuthTest, SharingWithAUserAndWithEveryone) {
  const std::string b_mesh = upload(bob_);
  const std::string target = "/api/v1/meshes/" + b_mesh;
  EXPECT_EQ(call(alice_, "GET", target).status, 404);
  const HttpResponse shared = call(bob_, "POST", target + "/share", R"({"users":["alice"]})");
  ASSERT_EQ(shared.status, 200) << shared.body;
  EXPECT_EQ(json::parse(shared.body)["users"], json::array({"alice"}));
  EXPECT_EQ(call(alice_, "GET", target).status, 200);
  EXPECT_NE(call(alice_, "GET", "/api/v1/meshes").body.find(b_mesh), std::string::npos);
  EXPECT_EQ(call(alice_, "GET", target + "/download?format=obj").status, 200);
  // A reads it, runs a job on it (her job), but does not delete or reshare it.
  const std::string a_job = run_job(alice_, {{"algorithm", "test_translate"}, {"inputs", {{"mesh", b_mesh}}}});
  EXPECT_EQ(call(bob_, "GET", "/api/v1/jobs/" + a_job).status, 404);
  EXPECT_EQ(call(alice_, "DELETE", target).status, 403);
  EXPECT_EQ(call(alice_, "POST", target + "/share", R"({"everyone":true})").status, 403);
  // Unknown users and bad bodies are 400.
  EXPECT_EQ(call(bob_, "POST", target + "/share", R"({"users":["mallory"]})").status, 400);
  EXPECT_EQ(call(bob_, "POST", target + "/share", R"({"users":"alice"})").status, 400);
  EXPECT_EQ(call(bob_, "POST", target + "/share", "{}").status, 400);
  // Unshared: 404 again.
  ASSERT_EQ(call(bob_, "POST", target + "/unshare", R"({"users":["alice"]})").status, 200);
  EXPECT_EQ(call(alice_, "GET", target).status, 404);
  // With everyone, as a teacher shares a sample set.
  const HttpResponse everyone = call(bob_, "POST", target + "/share", R"({"everyone":true})");
  ASSERT_EQ(everyone.status, 200) << everyone.body;
  EXPECT_EQ(json::parse(everyone.body)["everyone"], true);
  EXPECT_EQ(call(alice_, "GET", target).status, 200);
  EXPECT_EQ(call(bob_, "DELETE", target).status, 204);
  EXPECT_EQ(call(alice_, "GET", target).status, 404);
}

TEST_F(AuthTest, SharingAJobSharesItsStateAndArtifactsReadOnly) {
  const std::string b_mesh = upload(bob_);
  const std::string b_job = run_job(bob_, {{"algorithm", "test_translate"}, {"inputs", {{"mesh", b_mesh}}}});
  const std::string target = "/api/v1/jobs/" + b_job;
  ASSERT_EQ(call(bob_, "POST", target + "/share", R"({"users":["alice"]})").status, 200);
  EXPECT_EQ(call(alice_, "GET", target).status, 200);
  EXPECT_NE(call(alice_, "GET", "/api/v1/jobs").body.find(b_job), std::string::npos);
  EXPECT_EQ(call(alice_, "GET", target + "/artifacts/mesh").status, 200);
  // Its output mesh as her job's input: stored as her own mesh.
  const std::string a_job = run_job(
      alice_, {{"algorithm", "test_translate"}, {"inputs", {{"mesh", {{"job", b_job}, {"artifact", "mesh"}}}}}});
  const json a_input = json::parse(call(alice_, "GET", "/api/v1/jobs/" + a_job).body)["inputs"]["mesh"];
  EXPECT_EQ(json::parse(call(alice_, "GET", "/api/v1/meshes/" + a_input.get<std::string>()).body)["owner"], "alice");
  // B's input mesh stays his.
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes/" + b_mesh).status, 404);
  EXPECT_EQ(call(alice_, "DELETE", target).status, 403);
  EXPECT_EQ(call(alice_, "POST", target + "/share", R"({"everyone":true})").status, 403);
  ASSERT_EQ(call(bob_, "POST", target + "/unshare", R"({"users":["alice"]})").status, 200);
  EXPECT_EQ(call(alice_, "GET", target).status, 404);
  EXPECT_EQ(call(alice_, "GET", target + "/artifacts/mesh").status, 404);
}

TEST_F(AuthTest, EventsGoOnlyToThoseWhoMayReadThem) {
  std::vector<std::pair<json, Access>> events;
  router_->on_event = [&](const json& e, const Access& a) { events.emplace_back(e, a); };
  const std::string b_mesh = upload(bob_);
  ASSERT_EQ(events.size(), 1u);
  EXPECT_TRUE(events[0].second.allows({"bob", false}));
  EXPECT_FALSE(events[0].second.allows({"alice", false}));
  EXPECT_TRUE(events[0].second.allows({"root", true}));
  call(bob_, "POST", "/api/v1/meshes/" + b_mesh + "/share", R"({"users":["alice"]})");
  call(bob_, "DELETE", "/api/v1/meshes/" + b_mesh);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[1].first["type"], "mesh_deleted");
  EXPECT_TRUE(events[1].second.allows({"alice", false}));  // she had it in her list
  EXPECT_FALSE(events[1].second.allows({"carol", false}));
}

TEST_F(AuthTest, RevokedTokensStopWorkingAtOnce) {
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes").status, 200);
  const std::string second = Auth(*store_, true).add_user("alice", false);
  EXPECT_EQ(store_->revoke_tokens("alice"), 2);
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes").status, 401);
  EXPECT_EQ(call(second, "GET", "/api/v1/meshes").status, 401);
  EXPECT_EQ(call(bob_, "GET", "/api/v1/meshes").status, 200);
  // A new token for the same user works, and her data is still hers.
  EXPECT_EQ(call(Auth(*store_, true).add_user("alice", false), "GET", "/api/v1/meshes").status, 200);
}

TEST_F(AuthTest, TokensAreStoredHashed) {
  // cgv_ID_SECRET: the store has ID and SHA-256(SECRET), never the secret.
  ASSERT_EQ(alice_.size(), 4u + 16 + 1 + 64);
  const auto row = store_->find_token(alice_.substr(4, 16));
  ASSERT_TRUE(row);
  EXPECT_EQ(row->first, "alice");
  EXPECT_EQ(row->second, sha256_hex(alice_.substr(21)));
  std::ifstream db(dir_ / "cgview.db", std::ios::binary);
  std::stringstream bytes;
  bytes << db.rdbuf();
  EXPECT_EQ(bytes.str().find(alice_.substr(21)), std::string::npos);
  // A token with its secret changed is refused.
  std::string wrong = alice_;
  wrong.back() = wrong.back() == '0' ? '1' : '0';
  EXPECT_EQ(call(wrong, "GET", "/api/v1/meshes").status, 401);
  EXPECT_EQ(call(alice_, "GET", "/api/v1/meshes").status, 200);
  // The scheme's name is case-insensitive.
  EXPECT_EQ(router_->handle({"GET", "/api/v1/meshes", "", "bearer " + alice_}).status, 200);
  EXPECT_THROW(Auth(*store_, true).add_user("local", false), InvalidInput);
  EXPECT_THROW(Auth(*store_, true).add_user("a b", false), InvalidInput);
}

// Without --auth required (loopback), a request with no token is the local
// user, who sees everything; a wrong token is still refused.
TEST_F(AuthTest, LoopbackNeedsNoTokenButRefusesAWrongOne) {
  const std::string b_mesh = upload(bob_);
  RouterConfig rc;
  rc.jobs = jobs_.get();
  Router open(*meshes_, rc);
  const HttpResponse list = open.handle({"GET", "/api/v1/meshes", "", ""});
  ASSERT_EQ(list.status, 200);
  EXPECT_NE(list.body.find(b_mesh), std::string::npos);
  EXPECT_EQ(open.handle({"GET", "/api/v1/meshes", "", "Bearer nonsense"}).status, 401);
  EXPECT_EQ(open.handle({"GET", "/api/v1/meshes", "", "Bearer " + alice_}).body.find(b_mesh), std::string::npos);
}

}  // namespace
}  // namespace cgview::server
