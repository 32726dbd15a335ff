// A course on the real server, in the real sandbox: roles, a roster with
// one-time sign-in links, a join code, what is shared with a course and how
// removing a member ends it; an assignment graded on hidden meshes (a wrong,
// a right, a crashing and a non-compiling submission, scored against the
// reference's output with their reasons and pictures), identical regrades,
// late submissions, the grades as CSV; and every route by which a student
// might reach a hidden mesh or the reference's output, each refused.
//
// Each test makes the course it needs on its own server (each runs in its
// own process); the data lies under /var/tmp, since a job sees its own /tmp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "centroid_distance_plugin.h"
#include "server_harness.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

// The reference: the built-in centroid_distance as a plugin registering "distance".
std::string reference_source() { return centroid_distance_plugin(CGVIEW_SOURCE_DIR, "distance"); }

// The reference with one expression replaced: a student's variant.
std::string variant(const std::string& from, const std::string& to) {
  std::string s = reference_source();
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}
// A mesh-output algorithm: the input lifted along y by FRACTION of its height.
std::string lift_source(const std::string& fraction) {
  return R"(#include <algorithm>
#include <string>
#include <vector>

#include "registry/registry.h"

namespace cgview {
namespace {
struct LiftParams {
  bool again = false;
  template <class V>
  void describe(V& v) {
    v.boolean("again", again, {.label = "Again", .help = "unused"});
  }
};
struct LiftResult {
  Mesh lifted;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("lifted", lifted);
  }
};
LiftResult lift(const Mesh& mesh, const LiftParams& = {}, Context* = nullptr) {
  double lo = mesh.positions[0][1], hi = lo;
  for (const Vec3& v : mesh.positions) lo = std::min(lo, v[1]), hi = std::max(hi, v[1]);
  LiftResult r{mesh, {}};
  for (Vec3& v : r.lifted.positions) v[1] += )" +
         fraction + R"( * (hi - lo);
  return r;
}
CGVIEW_REGISTER_FUNCTION(lift, lift, {.title = "Lift", .description = "Lifts the mesh.", .area = "playground"})
}  // namespace
}  // namespace cgview
)";
}

const std::string kDistance = "field.values[i] = float(std::pow(norm(mesh.positions[i] - c), p.exponent));";

class Course : public ServerFixture {
 protected:
  Course() : ServerFixture("courses-", true) {}
  void SetUp() override {
    ServerFixture::SetUp();
    teacher_ = server_command(data_, "user add tina --role teacher");
    alice_ = server_command(data_, "user add alice");
    bob_ = server_command(data_, "user add bob");
    eve_ = server_command(data_, "user add eve");
    ASSERT_TRUE(server_.start(data_, {"--auth", "required", "--job-timeout-s", "30", "--job-memory-mb", "2048"}, dir_));
  }
  HttpResult as(const std::string& token, const std::string& method, const std::string& target,
                const json& body = nullptr) {
    return call_as(port(), token, method, target, body.is_null() ? "" : body.dump());
  }
  std::string upload(const std::string& token, const std::string& name) {
    const HttpResult up = call_as(port(), token, "POST", "/api/v1/meshes?name=" + name, read_bytes(sample(name)));
    EXPECT_EQ(up.status, 201u) << up.body;
    return up.body_json().value("id", "");
  }
  json wait_for(const std::string& token, const std::string& target, const std::string& key,
                const std::vector<std::string>& until) {
    json j;
    for (int i = 0; i < 1200; ++i) {
      j = as(token, "GET", target).body_json();
      if (std::find(until.begin(), until.end(), j.value(key, "")) != until.end()) break;
      std::this_thread::sleep_for(50ms);
    }
    return j;
  }
  // A built plugin of the caller's: its id.
  std::string build(const std::string& token, const std::string& source) {
    const HttpResult c = as(token, "POST", "/api/v1/plugins", {{"name", "reference"}, {"source", source}});
    EXPECT_EQ(c.status, 201u) << c.body;
    const std::string id = c.body_json().value("id", "");
    const HttpResult b = as(token, "POST", "/api/v1/plugins/" + id + "/build");
    EXPECT_EQ(b.status, 202u) << b.body;
    const json job = wait_for(token, "/api/v1/jobs/" + b.body_json().value("id", ""), "state", {"done", "failed"});
    EXPECT_EQ(job.value("state", ""), "done") << job.dump();
    return id;
  }
  // The teacher's course with alice as a student: its id (made once).
  std::string course() {
    if (!course_.empty()) return course_;
    const HttpResult c = as(teacher_, "POST", "/api/v1/courses", {{"title", "Geometry Processing"}});
    EXPECT_EQ(c.status, 201u) << c.body;
    course_ = c.body_json().value("id", "");
    const HttpResult m = as(teacher_, "POST", "/api/v1/courses/" + course_ + "/members", json::array({"alice"}));
    EXPECT_EQ(m.status, 200u) << m.body;
    return course_;
  }
  // Posts an assignment on two hidden meshes, with pictures: its JSON as the teacher sees it.
  json post_assignment(const json& extra = json::object()) {
    if (reference_.empty()) {
      reference_ = build(teacher_, reference_source());
      hidden_ = {upload(teacher_, "elephant.off"), upload(teacher_, "blobby.off")};
      public_ = upload(teacher_, "sphere.off");
    }
    json body = {{"title", "Distance from the centroid"},
                 {"statement", "# Distances\nColour each vertex by its distance from the centroid."},
                 {"starter", "// your code here\n"},
                 {"public_meshes", {public_}},
                 {"hidden_meshes", hidden_},
                 {"reference_plugin", reference_},
                 {"compare", {{"method", "relative"}, {"tolerance", 0.03}}},
                 {"points_per_mesh", 5},
                 {"show_pictures", true},
                 {"time_limit_s", 10}};
    body.update(extra);
    const HttpResult a = as(teacher_, "POST", "/api/v1/courses/" + course() + "/assignments", body);
    EXPECT_EQ(a.status, 201u) << a.body;
    return a.body_json();
  }
  json submit_and_wait(const std::string& token, const std::string& assignment, const std::string& source) {
    const HttpResult s = as(token, "POST", "/api/v1/assignments/" + assignment + "/submissions", {{"source", source}});
    EXPECT_EQ(s.status, 202u) << s.body;
    return wait_for(token, "/api/v1/submissions/" + s.body_json().value("id", ""), "state", {"graded", "failed"});
  }

  std::string teacher_, alice_, bob_, eve_, course_, reference_, public_;
  std::vector<std::string> hidden_;
};

TEST_F(Course, OnlyATeacherCreatesCoursesAndTheRoleShowsInTheUserList) {
  const HttpResult refused = as(alice_, "POST", "/api/v1/courses", {{"title", "Mine"}});
  EXPECT_EQ(refused.status, 403u) << refused.body;
  EXPECT_NE(refused.body_json().value("detail", "").find("--role teacher"), std::string::npos) << refused.body;
  EXPECT_EQ(as(teacher_, "POST", "/api/v1/courses", json::object()).status, 400u);
  const std::string list = server_command(data_, "user list");
  EXPECT_NE(list.find("\ntina "), std::string::npos) << list;
  EXPECT_EQ(list.substr(list.find("\ntina ") + 1, 40).find(" teacher "), 24u) << list;
  const json mine = as(teacher_, "GET", "/api/v1/courses/" + course()).body_json();
  EXPECT_EQ(mine.value("role", ""), "teacher");
  EXPECT_FALSE(mine.value("join_code", "").empty());
  // A student sees the course, not its members or join code; another user sees nothing.
  const json theirs = as(alice_, "GET", "/api/v1/courses/" + course()).body_json();
  EXPECT_EQ(theirs.value("role", ""), "student") << theirs.dump();
  EXPECT_FALSE(theirs.contains("members"));
  EXPECT_FALSE(theirs.contains("join_code"));
  EXPECT_EQ(as(bob_, "GET", "/api/v1/courses/" + course()).status, 404u);
}

TEST_F(Course, ARosterMakesAccountsWhoseOneTimeLinksSignTheStudentsIn) {
  const std::string csv = "login,name\nsam,\"Sam, S.\"\nkim,Kim K\nalice,Alice A\n";
  const HttpResult r =
      call_as(port(), teacher_, "POST", "/api/v1/courses/" + course() + "/members?link_expires_s=3600", csv);
  ASSERT_EQ(r.status, 200u) << r.body;
  const json out = r.body_json();
  EXPECT_EQ(out["created"], json({"sam", "kim"}));  // alice had an account: no link
  ASSERT_EQ(out["links"].size(), 2u);
  const std::string link = out["links"][0]["ticket"];
  // The link, redeemed once, is the student's token.
  const HttpResult red = http_call(port(), Method::post, "/api/v1/tickets/redeem", json{{"ticket", link}}.dump());
  ASSERT_EQ(red.status, 200u) << red.body;
  EXPECT_EQ(red.body_json().value("user", ""), "sam");
  const std::string sam = red.body_json().value("token", "");
  const json courses = as(sam, "GET", "/api/v1/courses").body_json();
  ASSERT_EQ(courses.size(), 1u) << courses.dump();
  EXPECT_EQ(courses[0].value("role", ""), "student");
  EXPECT_EQ(http_call(port(), Method::post, "/api/v1/tickets/redeem", json{{"ticket", link}}.dump()).status, 401u);
  // Names with commas survive; a bad line is named and nothing of its roster is kept.
  const json members = as(teacher_, "GET", "/api/v1/courses/" + course()).body_json()["members"];
  bool found = false;
  for (const json& m : members) found = found || (m["login"] == "sam" && m["name"] == "Sam, S.");
  EXPECT_TRUE(found) << members.dump();
  const HttpResult bad = call_as(port(), teacher_, "POST", "/api/v1/courses/" + course() + "/members",
                                 "login,name\nzed,Zed\nno way,Bad\n");
  EXPECT_EQ(bad.status, 400u);
  EXPECT_NE(bad.body.find("line 3"), std::string::npos) << bad.body;
  EXPECT_EQ(server_command(data_, "user list").find("zed"), std::string::npos);
  // A link lives a week at most; only a teacher enrols.
  EXPECT_EQ(
      call_as(port(), teacher_, "POST", "/api/v1/courses/" + course() + "/members?link_expires_s=999999", "x").status,
      400u);
  EXPECT_EQ(as(alice_, "POST", "/api/v1/courses/" + course() + "/members", json::array({"bob"})).status, 403u);
}

TEST_F(Course, WhatIsSharedWithACourseItsMembersReadUntilTheyAreRemoved) {
  const std::string mesh = upload(teacher_, "cube.off");
  ASSERT_EQ(as(teacher_, "POST", "/api/v1/meshes/" + mesh + "/share", {{"courses", {course()}}}).status, 200u);
  // bob joins with the code, as a student.
  const std::string code = as(teacher_, "GET", "/api/v1/courses/" + course()).body_json().value("join_code", "");
  EXPECT_EQ(as(bob_, "POST", "/api/v1/courses/join", {{"code", "wrong"}}).status, 404u);
  const HttpResult joined = as(bob_, "POST", "/api/v1/courses/join", {{"code", code}});
  ASSERT_EQ(joined.status, 200u) << joined.body;
  EXPECT_EQ(joined.body_json().value("role", ""), "student");
  EXPECT_EQ(as(bob_, "GET", "/api/v1/meshes/" + mesh).status, 200u);
  EXPECT_EQ(as(bob_, "DELETE", "/api/v1/meshes/" + mesh).status, 403u);  // read-only
  EXPECT_EQ(as(eve_, "GET", "/api/v1/meshes/" + mesh).status, 404u);     // not a member
  // Only a member shares with a course.
  const std::string eves = upload(eve_, "cube.off");
  EXPECT_EQ(as(eve_, "POST", "/api/v1/meshes/" + eves + "/share", {{"courses", {course()}}}).status, 404u);
  // Over a WebSocket opened before his removal too.
  WsClient ws;
  ASSERT_FALSE(ws.connect(port()));
  ASSERT_FALSE(ws.send({{"type", "auth"}, {"token", bob_}, {"request_id", 1}}));
  ASSERT_EQ(ws.reply().value("type", ""), "authenticated");
  ASSERT_FALSE(ws.send({{"type", "get_mesh"}, {"mesh_id", mesh}, {"request_id", 2}}));
  EXPECT_EQ(ws.reply().value("type", ""), "mesh_begin");
  for (auto m = ws.read(); m && (m->binary || m->data.find("\"mesh_end\"") == std::string::npos); m = ws.read()) {
  }
  // Removed, bob reads it no more, at once.
  ASSERT_EQ(as(teacher_, "DELETE", "/api/v1/courses/" + course() + "/members/bob").status, 204u);
  EXPECT_EQ(as(bob_, "GET", "/api/v1/meshes/" + mesh).status, 404u);
  ASSERT_FALSE(ws.send({{"type", "get_mesh"}, {"mesh_id", mesh}, {"request_id", 3}}));
  const json after = ws.reply();
  EXPECT_EQ(after.value("error", ""), "not_found") << after.dump();
  EXPECT_EQ(as(bob_, "GET", "/api/v1/courses/" + course()).status, 404u);
}

TEST_F(Course, AnAssistantSeesTheCourseButChangesNothing) {
  ASSERT_EQ(as(teacher_, "POST", "/api/v1/courses/" + course() + "/members",
               json::array({{{"login", "eve"}, {"role", "assistant"}}}))
                .status,
            200u);
  const json c = as(eve_, "GET", "/api/v1/courses/" + course()).body_json();
  EXPECT_EQ(c.value("role", ""), "assistant");
  EXPECT_TRUE(c.contains("members"));
  EXPECT_FALSE(c.contains("join_code"));
  EXPECT_EQ(as(eve_, "POST", "/api/v1/courses/" + course() + "/assignments", {{"title", "x"}}).status, 403u);
  EXPECT_EQ(as(eve_, "DELETE", "/api/v1/courses/" + course() + "/members/alice").status, 403u);
}

TEST_F(Course, SubmissionsAreScoredOnTheHiddenMeshesWithTheirReasonsAndPictures) {
  const json a = post_assignment();
  const std::string id = a.value("id", "");
  // The student reads the statement and the public mesh, never the hidden ones.
  const json seen = as(alice_, "GET", "/api/v1/assignments/" + id).body_json();
  EXPECT_EQ(seen.value("statement", "").substr(0, 11), "# Distances");
  EXPECT_FALSE(seen.contains("hidden_meshes"));
  EXPECT_FALSE(seen.contains("reference_jobs"));
  EXPECT_EQ(seen.value("hidden_count", 0), 2);
  EXPECT_EQ(as(alice_, "GET", "/api/v1/meshes/" + public_).status, 200u);

  // Wrong: every distance 10% too far.
  const json wrong =
      submit_and_wait(alice_, id, variant(kDistance, kDistance.substr(0, kDistance.size() - 2) + " * 1.1f);"));
  ASSERT_EQ(wrong.value("state", ""), "graded") << wrong.dump();
  EXPECT_EQ(wrong.value("score", -1.0), 0.0);
  EXPECT_EQ(wrong.value("max_score", 0.0), 10.0);
  for (const json& r : wrong["results"]) {
    EXPECT_NE(r.value("reason", "").find("over the 3% allowed"), std::string::npos) << r.dump();
    EXPECT_FALSE(r.contains("job"));
    EXPECT_FALSE(r.contains("mesh_id"));
  }
  // Right: the reference's own code, scored full; its pictures are PNGs.
  const json right = submit_and_wait(alice_, id, reference_source());
  ASSERT_EQ(right.value("state", ""), "graded") << right.dump();
  EXPECT_EQ(right.value("score", -1.0), 10.0) << right.dump();
  EXPECT_NE(right["results"][0].value("reason", "").find("within tolerance"), std::string::npos);
  const HttpResult png = as(alice_, "GET", right["results"][0]["pictures"].value("result", ""));
  ASSERT_EQ(png.status, 200u) << png.body;
  EXPECT_EQ(png.body.substr(1, 3), "PNG");
  EXPECT_EQ(as(bob_, "GET", right["results"][0]["pictures"].value("result", "")).status, 404u);

  // Crashing and not compiling: the kind of failure, never the run's text.
  const json crash = submit_and_wait(alice_, id, variant(kDistance, "*(volatile int*)nullptr = 1;"));
  ASSERT_EQ(crash.value("state", ""), "graded") << crash.dump();
  EXPECT_EQ(crash["results"][0].value("reason", ""), "crashed: segmentation fault") << crash.dump();
  const json broken = submit_and_wait(alice_, id, variant(kDistance, "this is not C++"));
  EXPECT_EQ(broken.value("state", ""), "failed") << broken.dump();
  EXPECT_FALSE(broken["build"]["diagnostics"].empty());
  // Looping: stopped at ten times the reference's own run on each mesh (at
  // least 1 s), not at the assignment's 10 s.
  const json loop = submit_and_wait(alice_, id, variant(kDistance, "for (volatile int k = 0;; ++k) {}"));
  ASSERT_EQ(loop.value("state", ""), "graded") << loop.dump();
  const json refs = a["reference_jobs"];
  ASSERT_EQ(refs.size(), loop["results"].size());
  for (std::size_t i = 0; i < refs.size(); ++i) {
    const json ref = as(teacher_, "GET", "/api/v1/jobs/" + refs[i].get<std::string>()).body_json();
    const double run_s = ref.value("run_s", 0.0);
    ASSERT_GT(run_s, 0.0) << ref.dump();
    ASSERT_LT(run_s, 0.9) << "the reference is too slow here for its limit to differ from the teacher's";
    char limit[32];  // as API.md says: 10 times the reference's run, at least 1 s, at most time_limit_s
    std::snprintf(limit, sizeof limit, "%g", std::max(1.0, 10 * run_s));
    EXPECT_EQ(loop["results"][i].value("reason", ""),
              std::string("time limit: it ran past ") + limit + " s, this mesh's limit (ten times the reference's run)")
        << loop.dump();
  }

  // The teacher sees all five, with the runs; the grades count the latest (the loop).
  const json all = as(teacher_, "GET", "/api/v1/assignments/" + id + "/submissions").body_json();
  ASSERT_EQ(all.size(), 5u);
  EXPECT_FALSE(all[0]["results"][0].value("job", "").empty());
  const HttpResult csv = as(teacher_, "GET", "/api/v1/assignments/" + id + "/grades?format=csv");
  ASSERT_EQ(csv.status, 200u) << csv.body;
  EXPECT_EQ(csv.body.substr(0, csv.body.find('\n')),
            "Student,ID,SIS User ID,SIS Login ID,Section,Distance from the centroid (10 points),Submissions,Submitted,"
            "Late");
  EXPECT_NE(csv.body.find("\nalice,,alice,alice,,0,5,"), std::string::npos) << csv.body;
  EXPECT_EQ(as(alice_, "GET", "/api/v1/assignments/" + id + "/grades").status, 403u);
  // Another student sees none of them.
  EXPECT_EQ(as(alice_, "GET", "/api/v1/assignments/" + id + "/submissions").body_json().size(), 5u);
  EXPECT_EQ(as(bob_, "GET", "/api/v1/submissions/" + right.value("id", "")).status, 404u);

  // Graded again, every submission gets the same scores.
  ASSERT_EQ(as(teacher_, "POST", "/api/v1/assignments/" + id + "/regrade").status, 202u);
  const json again = wait_for(alice_, "/api/v1/submissions/" + right.value("id", ""), "state", {"graded"});
  EXPECT_EQ(again.value("score", -1.0), 10.0);
  EXPECT_EQ(again["results"], right["results"]);
  const json wrong_again = wait_for(alice_, "/api/v1/submissions/" + wrong.value("id", ""), "state", {"graded"});
  EXPECT_EQ(wrong_again["results"], wrong["results"]);
}

// A mesh output is compared in the sandbox, as a job of its own: its cost is
// its shape's, which the student's code made.
TEST_F(Course, AMeshOutputIsScoredByItsHausdorffDistanceToTheReferences) {
  reference_ = build(teacher_, lift_source("0.0"));
  hidden_ = {upload(teacher_, "blobby.off")};
  public_ = upload(teacher_, "sphere.off");
  const json a = post_assignment({{"compare", {{"method", "hausdorff"}, {"tolerance", 0.01}}}});
  ASSERT_EQ(a.value("output", ""), "lifted") << a.dump();
  const std::string id = a.value("id", "");
  const json wrong = submit_and_wait(alice_, id, lift_source("0.05"));
  ASSERT_EQ(wrong.value("state", ""), "graded") << wrong.dump();
  EXPECT_EQ(wrong.value("score", -1.0), 0.0);
  EXPECT_NE(wrong["results"][0].value("reason", "").find("Hausdorff distance"), std::string::npos) << wrong.dump();
  const json right = submit_and_wait(alice_, id, lift_source("0.0"));
  EXPECT_EQ(right.value("score", -1.0), 5.0) << right.dump();
  // Its pictures: the student's mesh and the reference's, drawn as they are.
  const HttpResult png = as(alice_, "GET", right["results"][0]["pictures"].value("result", ""));
  ASSERT_EQ(png.status, 200u) << png.body;
  EXPECT_EQ(png.body.substr(1, 3), "PNG");
  EXPECT_FALSE(right["results"][0]["pictures"].contains("difference"));
  // The staff see the measure: a lift of 5% of the height, over the diagonal.
  const json staff = as(teacher_, "GET", "/api/v1/submissions/" + wrong.value("id", "")).body_json();
  const double h = staff["results"][0]["measures"].value("hausdorff", 0.0);
  EXPECT_GT(h, 0.01);
  EXPECT_LT(h, 0.05);
}

TEST_F(Course, NoRouteGivesAStudentAHiddenMeshOrTheReferencesOutput) {
  const json a = post_assignment({{"show_pictures", false}});
  const std::string id = a.value("id", "");
  // A plugin that writes the hidden mesh's coordinates into its field.
  const json spy = submit_and_wait(alice_, id, variant(kDistance, "field.values[i] = float(mesh.positions[i].x);"));
  ASSERT_EQ(spy.value("state", ""), "graded") << spy.dump();
  const json staff = as(teacher_, "GET", "/api/v1/submissions/" + spy.value("id", "")).body_json();
  const std::string run = staff["results"][0].value("job", "");
  ASSERT_FALSE(run.empty());
  EXPECT_EQ(as(teacher_, "GET", "/api/v1/jobs/" + run).status, 200u);  // the staff read it
  for (const std::string& target :
       {"/api/v1/meshes/" + hidden_[0], "/api/v1/meshes/" + hidden_[0] + "/download",
        "/api/v1/meshes/" + hidden_[0] + "/render.png", "/api/v1/jobs/" + run,
        "/api/v1/jobs/" + run + "/artifacts/distance", "/api/v1/jobs/" + a["reference_jobs"][0].get<std::string>(),
        "/api/v1/jobs/" + a["reference_jobs"][0].get<std::string>() + "/artifacts/distance"})
    EXPECT_EQ(as(alice_, "GET", target).status, 404u) << target;
  const std::string listed = as(alice_, "GET", "/api/v1/jobs").body + as(alice_, "GET", "/api/v1/meshes").body;
  EXPECT_EQ(listed.find(run), std::string::npos);
  EXPECT_EQ(listed.find(hidden_[0]), std::string::npos);
  EXPECT_EQ(listed.find(a["reference_jobs"][0].get<std::string>()), std::string::npos);
  // Pictures are off for this assignment; the reasons carry no value of the run.
  EXPECT_EQ(as(alice_, "GET", "/api/v1/submissions/" + spy.value("id", "") + "/pictures/0/result.png").status, 403u);
  const json seen = as(alice_, "GET", "/api/v1/submissions/" + spy.value("id", "")).body_json();
  for (const json& r : seen["results"]) {
    EXPECT_FALSE(r.contains("pictures"));
    EXPECT_FALSE(r.contains("measures"));
  }
  // The WebSocket streams no hidden mesh either.
  WsClient ws;
  ASSERT_FALSE(ws.connect(port()));
  ASSERT_FALSE(ws.send({{"type", "auth"}, {"token", alice_}, {"request_id", 1}}));
  ASSERT_EQ(ws.reply().value("type", ""), "authenticated");
  ASSERT_FALSE(ws.send({{"type", "get_mesh"}, {"mesh_id", hidden_[0]}, {"request_id", 2}}));
  const json r = ws.reply();
  EXPECT_EQ(r.value("type", ""), "error") << r.dump();
  // An assistant reads the hidden meshes (to open the runs on them); a student never.
  ASSERT_EQ(as(teacher_, "POST", "/api/v1/courses/" + course() + "/members",
               json::array({{{"login", "eve"}, {"role", "assistant"}}}))
                .status,
            200u);
  EXPECT_EQ(as(eve_, "GET", "/api/v1/meshes/" + hidden_[0]).status, 200u);
  EXPECT_EQ(as(eve_, "GET", "/api/v1/jobs/" + run).status, 200u);
  // A public mesh is shared with the course by posting: it must be the teacher's to share.
  const std::string bobs = upload(bob_, "cube.off");
  ASSERT_EQ(as(bob_, "POST", "/api/v1/meshes/" + bobs + "/share", {{"users", {"tina"}}}).status, 200u);
  const HttpResult not_theirs =
      as(teacher_, "POST", "/api/v1/courses/" + course() + "/assignments",
         {{"title", "x"}, {"public_meshes", {bobs}}, {"hidden_meshes", hidden_}, {"reference_plugin", reference_}});
  EXPECT_EQ(not_theirs.status, 403u) << not_theirs.body;
  EXPECT_EQ(as(alice_, "GET", "/api/v1/meshes/" + bobs).status, 404u);
  // A hidden mesh must be the teacher's own and shared with nobody.
  const std::string shared = upload(teacher_, "cube.off");
  ASSERT_EQ(as(teacher_, "POST", "/api/v1/meshes/" + shared + "/share", {{"everyone", true}}).status, 200u);
  const HttpResult refused = as(teacher_, "POST", "/api/v1/courses/" + course() + "/assignments",
                                {{"title", "x"}, {"hidden_meshes", {shared}}, {"reference_plugin", reference_}});
  EXPECT_EQ(refused.status, 400u);
  EXPECT_NE(refused.body.find("unshare"), std::string::npos) << refused.body;
}

TEST_F(Course, ALateSubmissionIsMarkedAndCountsOnlyWhenTheTeacherSaysSo) {
  const json a = post_assignment({{"deadline", "2020-01-01T00:00:00Z"}});
  const std::string id = a.value("id", "");
  const json late = submit_and_wait(alice_, id, reference_source());
  EXPECT_TRUE(late.value("late", false)) << late.dump();
  EXPECT_EQ(late.value("score", -1.0), 10.0);
  auto alice_row = [&](const std::string& query) {
    const json grades = as(teacher_, "GET", "/api/v1/assignments/" + id + "/grades" + query).body_json();
    for (const json& r : grades["students"])
      if (r["login"] == "alice") return r;
    return json();
  };
  EXPECT_TRUE(alice_row("")["score"].is_null()) << alice_row("").dump();
  EXPECT_EQ(alice_row("?late=include").value("score", -1.0), 10.0);
  EXPECT_EQ(as(teacher_, "GET", "/api/v1/assignments/" + id + "/grades?late=maybe").status, 400u);
}

}  // namespace
}  // namespace cgview::test
