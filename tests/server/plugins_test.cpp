// Users' plugins on the real server, in the real sandbox (bubblewrap): a
// plugin saved, built (its compile errors as data, at their lines), run by
// the API with results equal to the built-in algorithm it copies, unknown
// to another user until shared; a hostile plugin's every way out (the
// server's database, another user's job, a write outside its directory,
// sockets to the server and the outside, a fork bomb, 10 GB of memory, an
// endless loop, a 10 GB file, a segfault) fails that job alone, with the
// limit it hit in its message, while another user's job goes on; the lab's
// plugin directory is picked up, and a changed file rebuilt, without a
// restart; a server killed with SIGKILL leaves no sandbox running; a server
// that cannot sandbox says so and refuses users' plugins.  The server's own
// side of the boundary: nothing a job leaves in its directory (a link as
// its error, its stderr or an artifact, a FIFO, /dev/zero, a huge
// result.json, thousands of files, a link as its /tmp for the next run) is
// followed, read without a cap or trusted, and a job's environment is not
// the server's.  The data lies under /var/tmp: a job sees its own /tmp, so
// data under /tmp would be out of its sight whether or not it is hidden.
#include <gtest/gtest.h>

#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "centroid_distance_plugin.h"
#include "io/mesh_io.h"
#include "server_harness.h"
#include "sqlite_query.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

std::string source_file(const std::string& name) { return read_bytes(fs::path(CGVIEW_SOURCE_DIR) / name); }

// The built-in centroid_distance as a plugin file registering `name`: a
// plugin that must give what the built-in gives.
std::string template_as(const std::string& name) { return centroid_distance_plugin(CGVIEW_SOURCE_DIR, name); }

class Plugins : public ServerFixture {
 protected:
  Plugins() : ServerFixture("plugins-", true) {}
  void SetUp() override {
    ServerFixture::SetUp();
    alice_ = server_command(data_, "user add alice");
    bob_ = server_command(data_, "user add bob");
    ASSERT_FALSE(alice_.empty());
    // Alice has 100 MB: a job of hers that writes more is stopped as it writes.
    std::ofstream(dir_ / "config.json") << json{
        {"sandbox", {{"processes", 64}, {"file_mb", 64}}},
        {"users",
         {{"alice", {{"storage_mb", 100}}}}}}.dump();
    fs::create_directories(dir_ / "lab");
    // A secret of the server's environment, which no job may read.
    ::setenv("CGVIEW_TEST_SECRET", "hunter2", 1);
    ASSERT_TRUE(start(data_));
    ::unsetenv("CGVIEW_TEST_SECRET");
    alice_mesh_ = upload(alice_, "sphere.off");
    bob_mesh_ = upload(bob_, "sphere.off");
  }
  bool start(const fs::path& data) {
    return server_.start(data,
                         {"--auth", "required", "--config", (dir_ / "config.json").string(), "--job-timeout-s", "15",
                          "--job-memory-mb", "2048", "--job-files", "3000", "--plugin-dir", (dir_ / "lab").string()},
                         dir_);
  }
  HttpResult as(const std::string& token, const std::string& method, const std::string& target,
                const json& body = nullptr) {
    return call_as(port(), token, method, target, body.is_null() ? "" : body.dump());
  }
  std::string upload(const std::string& token, const std::string& sample_name) {
    const HttpResult up =
        call_as(port(), token, "POST", "/api/v1/meshes?name=" + sample_name, read_bytes(sample(sample_name)));
    EXPECT_EQ(up.status, 201u) << up.body;
    return up.body_json().value("id", "");
  }
  json wait_job(const std::string& token, const std::string& id) { return wait_job_end(port(), id, 60s, token); }
  // Saves and builds a plugin; the plugin as it stands after its build.
  json build(const std::string& token, const std::string& name, const std::string& source) {
    const HttpResult c = as(token, "POST", "/api/v1/plugins", {{"name", name}, {"source", source}});
    EXPECT_EQ(c.status, 201u) << c.body;
    const std::string id = c.body_json().value("id", "");
    const HttpResult b = as(token, "POST", "/api/v1/plugins/" + id + "/build");
    EXPECT_EQ(b.status, 202u) << b.body;
    const json job = wait_job(token, b.body_json().value("id", ""));
    EXPECT_EQ(job.value("state", ""), "done") << job.dump();
    return as(token, "GET", "/api/v1/plugins/" + id).body_json();
  }
  // A job of a plugin's algorithm, submitted (201 expected).
  HttpResult submit(const std::string& token, const std::string& plugin, const std::string& algorithm,
                    const std::string& mesh, const json& params) {
    const HttpResult r =
        as(token, "POST", "/api/v1/jobs",
           {{"algorithm", algorithm}, {"plugin", plugin}, {"inputs", {{"mesh", mesh}}}, {"params", params}});
    EXPECT_EQ(r.status, 201u) << r.body;
    return r;
  }
  json run(const std::string& token, const std::string& plugin, const std::string& algorithm, const std::string& mesh,
           const json& params) {
    return wait_job(token, submit(token, plugin, algorithm, mesh, params).body_json().value("id", ""));
  }
  // Alice's build of the hostile plugin (tests/server/plugins/escape.cpp): its id.
  std::string build_escape() {
    const json p = build(alice_, "escape", source_file("tests/server/plugins/escape.cpp"));
    EXPECT_EQ(p["build"]["state"], "ok") << p.dump();
    return p.value("id", "");
  }
  // A done job of Bob's, whose results Alice's plugin reaches for.
  json bobs_done_job() {
    const HttpResult r =
        as(bob_, "POST", "/api/v1/jobs", {{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", bob_mesh_}}}});
    const json bobs = wait_job(bob_, r.body_json().value("id", ""));
    EXPECT_EQ(bobs.value("state", ""), "done");
    return bobs;
  }
  std::string alice_, bob_, alice_mesh_, bob_mesh_;
};

TEST_F(Plugins, ABuiltPluginRunsAsTheBuiltInAlgorithmItCopiesAndIsListedForItsOwnerAlone) {
  const json p = build(alice_, "mine", template_as("mine_distance"));
  ASSERT_EQ(p["build"]["state"], "ok") << p.dump();
  EXPECT_EQ(p["build"]["algorithms"], json({"mine_distance"}));
  const std::string id = p["id"];
  const json params = {{"exponent", 2}, {"normalize", true}};
  const json mine = run(alice_, id, "mine_distance", alice_mesh_, params);
  ASSERT_EQ(mine.value("state", ""), "done") << mine.dump();
  EXPECT_EQ(mine["plugin"], id);
  // The reference: the built-in algorithm the file copies, on the same mesh.
  const HttpResult ref =
      as(alice_, "POST", "/api/v1/jobs",
         {{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", alice_mesh_}}}, {"params", params}});
  const json builtin = wait_job(alice_, ref.body_json().value("id", ""));
  ASSERT_EQ(builtin.value("state", ""), "done");
  const std::string a =
      as(alice_, "GET", "/api/v1/jobs/" + mine["id"].get<std::string>() + "/artifacts/distance?format=txt").body;
  const std::string b =
      as(alice_, "GET", "/api/v1/jobs/" + builtin["id"].get<std::string>() + "/artifacts/distance?format=txt").body;
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  // A misspelt parameter is refused at submission, from the build's description.
  const HttpResult bad = as(alice_, "POST", "/api/v1/jobs",
                            {{"algorithm", "mine_distance"},
                             {"plugin", id},
                             {"inputs", {{"mesh", alice_mesh_}}},
                             {"params", {{"exponnt", 2}}}});
  EXPECT_EQ(bad.status, 400u);
  EXPECT_NE(bad.body.find("exponent"), std::string::npos) << bad.body;
  // Alice's algorithms list it; Bob's do not, and Bob cannot see, run or change it.
  auto lists = [&](const std::string& token) {
    const json list =
        as(token, "GET", "/api/v1/algorithms").body_json();  // kept: a loop over a temporary's part dangles
    for (const auto& a : list["algorithms"])
      if (a.value("plugin", "") == id) return true;
    return false;
  };
  EXPECT_TRUE(lists(alice_));
  EXPECT_FALSE(lists(bob_));
  EXPECT_EQ(as(bob_, "GET", "/api/v1/plugins/" + id).status, 404u);
  EXPECT_EQ(as(bob_, "GET", "/api/v1/plugins").body_json()["plugins"].size(), 0u);
  const HttpResult bob_run = as(bob_, "POST", "/api/v1/jobs",
                                {{"algorithm", "mine_distance"}, {"plugin", id}, {"inputs", {{"mesh", bob_mesh_}}}});
  EXPECT_EQ(bob_run.status, 404u) << bob_run.body;
  // Bob's own plugin of the same name is his: names never clash between users.
  const json bobs = build(bob_, "mine", template_as("mine_distance"));
  EXPECT_EQ(bobs["build"]["state"], "ok");
  EXPECT_NE(bobs["id"], id);
  // Shared, Alice's runs for Bob too, and is still hers alone to change.
  EXPECT_EQ(as(alice_, "POST", "/api/v1/plugins/" + id + "/share", {{"users", {"bob"}}}).status, 200u);
  EXPECT_TRUE(lists(bob_));
  EXPECT_EQ(run(bob_, id, "mine_distance", bob_mesh_, json::object()).value("state", ""), "done");
  EXPECT_EQ(as(bob_, "PUT", "/api/v1/plugins/" + id, {{"name", "stolen"}}).status, 403u);
  EXPECT_EQ(as(bob_, "DELETE", "/api/v1/plugins/" + id).status, 403u);
  // Renamed and deleted by its owner.
  EXPECT_EQ(as(alice_, "PUT", "/api/v1/plugins/" + id, {{"name", "renamed"}}).body_json()["name"], "renamed");
  EXPECT_EQ(as(alice_, "DELETE", "/api/v1/plugins/" + id).status, 204u);
  EXPECT_EQ(as(alice_, "GET", "/api/v1/plugins/" + id).status, 404u);
}

TEST_F(Plugins, CompileErrorsComeBackAsDataAtTheirLines) {
  std::string src = template_as("broken");
  const std::string good = "field.values[i] = float(";
  const std::size_t at = src.find(good);
  ASSERT_NE(at, std::string::npos);
  src.replace(at, good.size(), "field.values[i] = flot(");
  const int line = 1 + int(std::count(src.begin(), src.begin() + long(at), '\n'));
  const int column = int(at - src.rfind('\n', at)) + int(std::string("field.values[i] = ").size());
  const json p = build(alice_, "broken", src);
  EXPECT_EQ(p["build"]["state"], "failed");
  ASSERT_FALSE(p["build"]["diagnostics"].empty()) << p.dump();
  const json d = p["build"]["diagnostics"][0];
  EXPECT_EQ(d["file"], "broken.cpp");
  EXPECT_EQ(d["line"], line);
  EXPECT_EQ(d["column"], column);
  EXPECT_EQ(d["severity"], "error");
  EXPECT_NE(d["message"].get<std::string>().find("flot"), std::string::npos);
  EXPECT_NE(p["build"]["error"].get<std::string>().find("broken.cpp:" + std::to_string(line)), std::string::npos);
  // A name taken by a built-in algorithm is refused as an error of the file.
  const json clash = build(alice_, "clash", template_as("centroid_distance"));
  EXPECT_EQ(clash["build"]["state"], "failed");
  EXPECT_NE(clash["build"]["error"].get<std::string>().find("centroid_distance"), std::string::npos);
}

TEST_F(Plugins, EveryWayOutOfTheSandboxFailsItsJobAloneWithTheLimitItHit) {
  const std::string id = build_escape();
  ASSERT_FALSE(id.empty());
  // Bob's job, and one of his results that Alice's plugin will look for.
  const json bobs = bobs_done_job();
  ASSERT_EQ(bobs.value("state", ""), "done");
  const fs::path bob_result = data_ / "jobs" / bobs["id"].get<std::string>() / "result.json";
  ASSERT_TRUE(fs::exists(bob_result));
  struct Attempt {
    std::string attempt, target, expect;
  };
  std::vector<Attempt> attempts = {
      {"read_file", (data_ / "cgview.db").string(), "the server's data and other jobs are not visible"},
      {"read_file", bob_result.string(), "the server's data and other jobs are not visible"},
      // The config file lies outside the data directory, readable by all:
      // hidden all the same (behind a /dev/null the job may not open).
      {"read_file", (dir_ / "config.json").string(), "a job reads only its inputs"},
      {"write_file", "/usr/cgview-escaped.txt", "a job writes only in its own directory"},
      {"write_file", (data_ / "escaped.txt").string(), "(the sandbox: "},
      {"connect_local", std::to_string(port()), "a job has no network"},
      {"connect_outside", "", "a job has no network"},
      {"fork_bomb", "", "process limit: 64"},
      {"allocate", "", "exceeded its memory limit of 2048 MB"},
      {"loop", "", "exceeded its time limit of 15 s"},
      {"big_file", "", "file-size limit of 64 MB"},
      {"segfault", "", "SIGSEGV"},
      // Not root, no capability, and none to gain by an exec.
      {"become_root", "",
       "; CapInh: 0000000000000000 CapPrm: 0000000000000000 CapEff: 0000000000000000 CapBnd: 0000000000000000 "
       "CapAmb: 0000000000000000 NoNewPrivs: 1"},
  };
  // A root server's jobs share the /dev it made once: read-only to all.
  // (Another user's bubblewrap makes each job a /dev of its own.)
  if (::geteuid() == 0)
    attempts.push_back({"write_file", "/dev/cgview-escaped.txt", "a job writes only in its own directory"});
  // Bob's long job runs beside them all.
  const HttpResult bob_long = as(bob_, "POST", "/api/v1/jobs",
                                 {{"algorithm", "sdf"}, {"inputs", {{"mesh", bob_mesh_}}}, {"params", {{"rays", 64}}}});
  ASSERT_EQ(bob_long.status, 201u) << bob_long.body;
  for (const Attempt& a : attempts) {
    const json j = run(alice_, id, "escape", alice_mesh_, {{"attempt", a.attempt}, {"target", a.target}});
    EXPECT_EQ(j.value("state", ""), "failed") << a.attempt << " " << a.target << ": " << j.dump();
    EXPECT_NE(j.value("error", json("")).get<std::string>().find(a.expect), std::string::npos)
        << a.attempt << ": " << j.value("error", json("")).dump();
    EXPECT_EQ(as(bob_, "GET", "/api/v1/health").status, 200u);
  }
  EXPECT_FALSE(fs::exists("/usr/cgview-escaped.txt"));
  EXPECT_FALSE(fs::exists(data_ / "escaped.txt"));
  EXPECT_EQ(wait_job(bob_, bob_long.body_json().value("id", "")).value("state", ""), "done");
  // The server's own files are as they were: Bob's result is still read back.
  EXPECT_EQ(as(bob_, "GET", "/api/v1/jobs/" + bobs["id"].get<std::string>() + "/artifacts/distance?format=txt").status,
            200u);
}

TEST_F(Plugins, AKilledServerLeavesNoSandboxRunning) {
  const std::string plugin = build_escape();
  ASSERT_FALSE(plugin.empty());
  const HttpResult r = submit(alice_, plugin, "escape", alice_mesh_, {{"attempt", "loop"}});
  ASSERT_EQ(r.status, 201u) << r.body;
  for (int i = 0; i < 200 && processes_naming(data_).empty(); ++i) std::this_thread::sleep_for(25ms);
  ASSERT_FALSE(processes_naming(data_).empty()) << "the looping job's sandbox never started";
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  for (const auto& [pid, cmdline] : processes_outliving(data_, 5s))
    ADD_FAILURE() << "outlived the server: " << pid << " " << cmdline.substr(0, 300);
}

TEST_F(Plugins, TheLabsPluginDirectoryIsPickedUpAndAChangedFileRebuiltWithoutARestart) {
  { std::ofstream(dir_ / "lab" / "lab_height.cpp") << template_as("lab_distance"); }
  auto lab = [&]() -> json {
    for (int i = 0; i < 600; ++i) {
      const json list = as(bob_, "GET", "/api/v1/plugins").body_json();
      for (const auto& p : list["plugins"])
        if (p.value("origin", "") == "lab" && p["build"].value("state", "") == "ok") return p;
      std::this_thread::sleep_for(100ms);
    }
    return nullptr;
  };
  const json first = lab();
  ASSERT_TRUE(first.is_object()) << as(bob_, "GET", "/api/v1/plugins").body << server_.stderr_text();
  EXPECT_EQ(first["build"]["algorithms"], json({"lab_distance"}));
  // Every user runs it, no one but the directory changes it.
  EXPECT_EQ(run(bob_, first["id"], "lab_distance", bob_mesh_, json::object()).value("state", ""), "done");
  EXPECT_EQ(run(alice_, first["id"], "lab_distance", alice_mesh_, json::object()).value("state", ""), "done");
  EXPECT_EQ(as(alice_, "PUT", "/api/v1/plugins/" + first["id"].get<std::string>(), {{"name", "x"}}).status, 403u);
  // The file changes (another algorithm name): the next look rebuilds it.
  std::this_thread::sleep_for(1100ms);  // a new modification time, whatever the filesystem's resolution
  { std::ofstream(dir_ / "lab" / "lab_height.cpp") << template_as("lab_distance_two"); }
  json second;
  for (int i = 0; i < 600; ++i) {
    second = as(bob_, "GET", "/api/v1/plugins/" + first["id"].get<std::string>()).body_json();
    if (second["build"]["algorithms"] == json({"lab_distance_two"}) && second["build"]["state"] == "ok") break;
    std::this_thread::sleep_for(100ms);
  }
  EXPECT_EQ(second["build"]["algorithms"], json({"lab_distance_two"})) << second.dump();
  EXPECT_EQ(run(bob_, first["id"], "lab_distance_two", bob_mesh_, json::object()).value("state", ""), "done");
}

TEST_F(Plugins, NothingAJobLeavesInItsDirectoryIsFollowedOrReadWithoutABound) {
  const std::string id = build_escape();
  ASSERT_FALSE(id.empty());
  // Bob's finished job, whose result must stay his and stay served.
  const json bobs = bobs_done_job();
  ASSERT_EQ(bobs.value("state", ""), "done");
  const std::string bob_field =
      as(bob_, "GET", "/api/v1/jobs/" + bobs["id"].get<std::string>() + "/artifacts/distance?format=txt").body;
  // What a link would reach: a file of the server's user outside the data
  // directory, the store itself, and Bob's result.
  const fs::path secret = dir_ / "secret.txt";
  { std::ofstream(secret) << "top secret: the server's own file\n"; }
  const fs::path db = data_ / "cgview.db";
  const fs::path bob_file = data_ / "jobs" / bobs["id"].get<std::string>() / "distance.f32";
  ASSERT_TRUE(fs::exists(bob_file));
  auto sized = [](const fs::path& f) { return f.string() + " " + std::to_string(fs::file_size(f)); };
  struct Attempt {
    std::string attempt, target, expect;
  };
  const std::vector<Attempt> attempts = {
      {"link_error", secret.string(), "error.txt is a link"},
      {"link_error", db.string(), "error.txt is a link"},
      {"zero_error", "", "error.txt is a link"},
      {"fifo_error", "", "error.txt is a FIFO, not a regular file"},
      {"link_artifact", sized(secret), "stolen.txt is a link"},
      {"link_artifact", sized(bob_file), "stolen.txt is a link"},
      {"link_artifact", sized(db), "stolen.txt is a link"},
      {"huge_result", "", "result.json has"},
      {"many_artifacts", "", "1000 artifacts, over the limit of 256"},
      {"many_files", "4000", "wrote more than 3000 files, the most a job may have"},
      {"fill_disk", "", "bytes its owner has left under their storage quota"},
      {"read_env", "CGVIEW_TEST_SECRET", "no variable names CGVIEW_TEST_SECRET"},
  };
  for (const Attempt& a : attempts) {
    const json j = run(alice_, id, "escape", alice_mesh_, {{"attempt", a.attempt}, {"target", a.target}});
    const std::string error = j.value("error", json("")).get<std::string>();
    EXPECT_EQ(j.value("state", ""), "failed") << a.attempt << " " << a.target << ": " << j.dump();
    EXPECT_NE(error.find(a.expect), std::string::npos) << a.attempt << ": " << error;
    EXPECT_EQ(error.find("top secret"), std::string::npos) << error;
    EXPECT_EQ(error.find("SQLite"), std::string::npos) << error;
    EXPECT_FALSE(fs::exists(data_ / "runs" / j.value("id", ""))) << "the run's directory outlived it";
    EXPECT_EQ(as(bob_, "GET", "/api/v1/health").status, 200u);
  }
  // Two jobs of 60 MB each, each under Alice's 100 MB, share her room while
  // they run: one of them is stopped.
  const std::string a = submit(alice_, id, "escape", alice_mesh_, {{"attempt", "fill_disk"}, {"target", "60"}})
                            .body_json()
                            .value("id", "");
  const std::string b = submit(alice_, id, "escape", alice_mesh_, {{"attempt", "fill_disk"}, {"target", "60"}})
                            .body_json()
                            .value("id", "");
  std::string stopped;
  for (const auto until = std::chrono::steady_clock::now() + 30s;
       stopped.empty() && std::chrono::steady_clock::now() < until; std::this_thread::sleep_for(50ms))
    for (const std::string& job : {a, b})
      if (as(alice_, "GET", "/api/v1/jobs/" + job).body_json().value("state", "") == "failed") stopped = job;
  ASSERT_FALSE(stopped.empty()) << "two jobs together wrote past her quota";
  EXPECT_NE(as(alice_, "GET", "/api/v1/jobs/" + stopped)
                .body_json()
                .value("error", json(""))
                .get<std::string>()
                .find("bytes its owner has left under their storage quota"),
            std::string::npos);
  const std::string other = stopped == a ? b : a;
  EXPECT_EQ(as(alice_, "DELETE", "/api/v1/jobs/" + other).status, 200u);
  EXPECT_EQ(wait_job(alice_, other).value("state", ""), "cancelled");
  // Nothing of theirs counts against Alice: her mesh and the failed jobs' logs alone.
  const json me = as(alice_, "GET", "/api/v1/me").body_json();
  EXPECT_LT(me.value("storage_bytes_used", std::uint64_t(0)), std::uint64_t(1) << 20) << me.dump();
  // The server, the store and Bob's result are as they were.
  EXPECT_EQ(integrity_check(db), "ok");
  EXPECT_EQ(as(bob_, "GET", "/api/v1/jobs/" + bobs["id"].get<std::string>() + "/artifacts/distance?format=txt").body,
            bob_field);
}

TEST_F(Plugins, ARunNeverGetsALinkAnEarlierRunLeftAsItsTmp) {
  const std::string plugin = build_escape();
  ASSERT_FALSE(plugin.empty());
  const HttpResult r = submit(alice_, plugin, "escape", alice_mesh_, {{"attempt", "link_tmp"}});
  ASSERT_EQ(r.status, 201u) << r.body;
  const std::string job = r.body_json().value("id", "");
  const fs::path tmp = data_ / "runs" / job / "work" / "tmp";
  auto linked = [&] {
    for (int i = 0; i < 400 && !fs::is_symlink(tmp); ++i) std::this_thread::sleep_for(25ms);
    return fs::is_symlink(tmp);
  };
  ASSERT_TRUE(linked()) << as(alice_, "GET", "/api/v1/jobs/" + job).body;
  // The server dies with the link in place; at its next start the job runs again.
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  ASSERT_TRUE(start(data_));
  // The second run got a fresh directory: it found no data as its /tmp, and planted its own link.
  ASSERT_TRUE(linked()) << as(alice_, "GET", "/api/v1/jobs/" + job).body;
  EXPECT_EQ(as(alice_, "GET", "/api/v1/jobs/" + job).body_json().value("state", ""), "running");
  EXPECT_EQ(as(alice_, "DELETE", "/api/v1/jobs/" + job).status, 200u);  // running: cancelled
  // Deleted at once, while its worker may still be stopping: gone for her
  // now, its directories once the worker has ended.
  EXPECT_EQ(as(alice_, "DELETE", "/api/v1/jobs/" + job).status, 204u);
  EXPECT_EQ(as(alice_, "GET", "/api/v1/jobs/" + job).status, 404u);
  EXPECT_EQ(as(alice_, "GET", "/api/v1/jobs").body.find(job), std::string::npos);
  auto gone = [&] { return !fs::exists(data_ / "runs" / job) && !fs::exists(data_ / "jobs" / job); };
  for (int i = 0; i < 400 && !gone(); ++i) std::this_thread::sleep_for(25ms);
  EXPECT_TRUE(gone());
  // Forgotten whole: her list answers, without it.
  const HttpResult list = as(alice_, "GET", "/api/v1/jobs");
  EXPECT_EQ(list.status, 200u) << list.body;
  EXPECT_EQ(list.body.find(job), std::string::npos);
}

TEST_F(Plugins, ARelativeDataDirectoryIsMadeAbsoluteAndStaysHidden) {
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_);
  const bool started = start("data");
  fs::current_path(cwd);
  ASSERT_TRUE(started);
  const std::string mesh = upload(alice_, "sphere.off");
  ASSERT_FALSE(mesh.empty());
  const HttpResult r =
      as(alice_, "POST", "/api/v1/jobs", {{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", mesh}}}});
  EXPECT_EQ(wait_job(alice_, r.body_json().value("id", "")).value("state", ""), "done");
  const json j = run(alice_, build_escape(), "escape", mesh,
                     {{"attempt", "read_file"}, {"target", (data_ / "cgview.db").string()}});
  EXPECT_NE(j.value("error", json("")).get<std::string>().find("not visible"), std::string::npos) << j.dump();
}

class NoSandbox : public ServerFixture {
 protected:
  NoSandbox() : ServerFixture("no-sandbox-") {}
};

TEST_F(NoSandbox, AServerThatCannotSandboxSaysSoAndRefusesUsersPlugins) {
  const std::string alice = server_command(data_, "user add alice");
  ASSERT_TRUE(server_.start(data_, {"--auth", "required", "--sandbox", "off"}, dir_));
  EXPECT_NE(server_.stderr_text().find("without a sandbox"), std::string::npos) << server_.stderr_text();
  const HttpResult r = call_as(port(), alice, "POST", "/api/v1/plugins",
                               json{{"name", "x"}, {"source", template_as("x_distance")}}.dump());
  EXPECT_EQ(r.status, 403u) << r.body;
  EXPECT_NE(r.body.find("cannot sandbox"), std::string::npos) << r.body;
}

}  // namespace
}  // namespace cgview::test
