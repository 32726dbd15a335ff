// Jobs against the real cgview-server with the test worker (cgview-worker-test):
// algorithms run in worker processes, artifacts in every format against an
// in-process run, bad requests, crashes, memory and time limits, cancellation,
// the result cache, WebSocket events and a server killed mid-job.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/errors.h"

#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "server_harness.h"
#include "store.h"
#include "frames.h"
#include "voxel/voxel_io.h"
#include "voxel_slice.h"
#include "sqlite_query.h"
#include "non_manifold_shapes.h"
#include "test_support.h"

#include <sqlite3.h>
#include <sys/stat.h>

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using test::http_call;
using test::http_get;
using test::Method;
using test::read_bytes;
using test::ServerProcess;
using test::WsClient;

// ---------------------------------------------------------------- jobs

constexpr int kMemoryMb = 512;
constexpr int kTimeoutS = 3;

class JobsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("jobs-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    data_ = dir_ / "data";
    ASSERT_TRUE(start());
    const std::string bytes = read_bytes(test::sample("sphere.off"));
    const auto r = http_call(server_.port(), Method::post, "/api/v1/meshes?name=sphere.off", bytes);
    ASSERT_EQ(r.status, 201) << r.body;
    mesh_id_ = r.body_json()["id"];
  }

  bool start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {
        "--worker",        test::bin("cgview-worker-test"), "--job-workers",   "2",
        "--job-timeout-s", std::to_string(kTimeoutS),       "--job-memory-mb", std::to_string(kMemoryMb)};
    args.insert(args.end(), extra.begin(), extra.end());
    return server_.start(data_, args, dir_);
  }

  json submit(const std::string& algorithm, const json& params, int expect = 201) {
    const json body = {{"algorithm", algorithm}, {"inputs", {{"mesh", mesh_id_}}}, {"params", params}};
    const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs", body.dump());
    EXPECT_EQ(r.status, expect) << r.body;
    return r.body_json();
  }

  json get(const std::string& id) { return http_get(server_.port(), "/api/v1/jobs/" + id).body_json(); }

  // Polls until the job leaves queued/running (or the limit); the last Job.
  json wait_end(const std::string& id, std::chrono::milliseconds limit = 20s) {
    return test::wait_job_end(server_.port(), id, limit);
  }

  json wait_state(const std::string& id, const std::string& state, std::chrono::milliseconds limit = 10s) {
    const auto deadline = Clock::now() + limit;
    json j;
    while (Clock::now() < deadline) {
      j = get(id);
      if (j.value("state", "") == state) return j;
      std::this_thread::sleep_for(10ms);
    }
    ADD_FAILURE() << "job " << id << " never became " << state << ": " << j.dump();
    return j;
  }

  std::string artifact(const std::string& id, const std::string& name, const std::string& format) {
    const auto r = http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/" + name + "?format=" + format);
    EXPECT_EQ(r.status, 200) << format << ": " << r.body;
    return r.body;
  }

  // The processes that run a job of this id: its job.json on their command
  // line, (a worker started ahead of its job) their stderr in its run's
  // directory, or (in the sandbox) its run's directory mounted in their
  // mount namespace.
  static std::set<pid_t> worker_pids(const std::string& job_id) {
    std::set<pid_t> found;
    for (const auto& e : fs::directory_iterator("/proc")) {
      const std::string cmd = read_bytes(e.path() / "cmdline");
      if (cmd.find("cgview-worker") == std::string::npos) continue;
      std::error_code ec;
      const std::string err = fs::read_symlink(e.path() / "fd" / "2", ec).string();
      const std::string run = "/runs/" + job_id + "/";
      if (cmd.find(job_id) != std::string::npos || err.find(job_id) != std::string::npos ||
          read_bytes(e.path() / "mountinfo").find(run) != std::string::npos)
        found.insert(pid_t(std::atoi(e.path().filename().c_str())));
    }
    return found;
  }
  static int worker_processes(const std::string& job_id) { return int(worker_pids(job_id).size()); }

  fs::path dir_, data_;
  ServerProcess server_;
  std::string mesh_id_;
};

TEST_F(JobsTest, ListsAlgorithmsWithoutTheTestOnes) {
  const json list = http_get(server_.port(), "/api/v1/algorithms").body_json();
  bool centroid = false;
  for (const auto& a : list["algorithms"]) {
    EXPECT_NE(a["area"], "test") << a["name"];
    centroid |= a["name"] == "centroid_distance";
  }
  EXPECT_TRUE(centroid) << list.dump();
}

TEST_F(JobsTest, CentroidDistanceArtifactsMatchAnInProcessRun) {
  const json job = submit("centroid_distance", {{"exponent", 2}});
  EXPECT_EQ(job["state"], "queued");
  EXPECT_EQ(job["cached"], false);
  const json done = wait_end(job["id"]);
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["progress"], 1.0);
  ASSERT_EQ(done["artifacts"].size(), 1u);
  EXPECT_EQ(done["artifacts"][0]["name"], "distance");
  EXPECT_EQ(done["artifacts"][0]["kind"], "scalar_field");
  EXPECT_EQ(done["artifacts"][0]["location"], "vertex");
  EXPECT_EQ(done["params"], (json{{"exponent", 2.0}, {"normalize", false}}));

  // The same computation in-process.
  const Mesh mesh = read_mesh_file(test::sample("sphere.off")).mesh;
  Context ctx;
  const AlgorithmResult direct = find_algorithm("centroid_distance").run(mesh, {{"exponent", 2.0}}, ctx);
  const auto& field = std::get<ScalarField>(direct.artifacts.at(0).value);

  const std::string id = done["id"];
  const std::string f32 = artifact(id, "distance", "f32");
  ASSERT_EQ(f32.size(), field.values.size() * 4);
  EXPECT_EQ(0, std::memcmp(f32.data(), field.values.data(), f32.size()));

  const json j = json::parse(artifact(id, "distance", "json"));
  EXPECT_EQ(j["location"], "vertex");
  EXPECT_EQ(j["hint"], "magnitude");
  ASSERT_EQ(j["values"].size(), field.values.size());
  for (std::size_t i = 0; i < field.values.size(); ++i) EXPECT_EQ(j["values"][i].get<float>(), field.values[i]) << i;
  EXPECT_EQ(j["range"][0].get<float>(), field.range().first);
  EXPECT_EQ(j["range"][1].get<float>(), field.range().second);

  for (const std::string format : {"txt", "csv", "ply"}) {
    const fs::path p = dir_ / ("direct." + format);
    write_artifact(direct.artifacts[0], mesh, p);
    EXPECT_EQ(artifact(id, "distance", format), read_bytes(p)) << format;
  }
  // A format a field has not: 400; no such artifact: 404.
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/distance?format=obj").status, 400);
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/nope").status, 404);

  // The same job again: answered from the cache, no worker run.
  const json again = submit("centroid_distance", {{"exponent", 2.0}, {"normalize", false}});
  EXPECT_EQ(again["state"], "done");
  EXPECT_EQ(again["cached"], true);
  EXPECT_NE(again["id"], id);
  EXPECT_FALSE(fs::exists(data_ / "jobs" / again["id"].get<std::string>())) << "a worker ran for a cached job";
  EXPECT_EQ(artifact(again["id"], "distance", "f32"), f32);
  // Other parameters are another job.
  EXPECT_EQ(submit("centroid_distance", {{"exponent", 3}})["cached"], false);
  // Listed.
  const json list = http_get(server_.port(), "/api/v1/jobs").body_json();
  EXPECT_GE(list["jobs"].size(), 3u);
}

TEST_F(JobsTest, VoxelizeJobServesItsGridAndSlicesOverWebSocket) {
  const json done = wait_end(submit("voxelize", {{"resolution", 32}, {"mode", "solid"}})["id"]);
  ASSERT_EQ(done["state"], "done") << done.dump();
  ASSERT_EQ(done["artifacts"][0]["kind"], "voxel_grid");
  const std::string id = done["id"];
  // The same grid in-process.
  const Mesh mesh = read_mesh_file(test::sample("sphere.off")).mesh;
  Context ctx;
  const AlgorithmResult direct = find_algorithm("voxelize").run(mesh, {{"resolution", 32LL}}, ctx);
  const auto& grid = std::get<VoxelGrid>(direct.artifacts.at(0).value);
  EXPECT_EQ(decode_nrrd(artifact(id, "grid", "nrrd")).bytes(), grid.bytes());
  EXPECT_EQ(decode_binvox(artifact(id, "grid", "binvox")).count_occupied(), grid.count_occupied());
  EXPECT_EQ(decode_vti(artifact(id, "grid", "vti")).bytes(), grid.bytes());
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id + "/artifacts/grid?format=obj").status, 400);

  WsClient ws;
  ASSERT_FALSE(ws.connect(server_.port()));
  const int k = grid.dims()[2] / 2;
  ASSERT_FALSE(ws.send(
      {{"type", "get_slice"}, {"request_id", 9}, {"job_id", id}, {"artifact", "grid"}, {"axis", "z"}, {"index", k}}));
  const json begin = ws.reply();
  ASSERT_EQ(begin["type"], "slice") << begin.dump();
  EXPECT_EQ(begin["request_id"], 9);
  EXPECT_EQ(begin["width"], grid.dims()[0]);
  EXPECT_EQ(begin["height"], grid.dims()[1]);
  std::string payload;
  for (int i = 0; i < begin["chunks"].get<int>(); ++i) {
    const auto m = ws.read();
    ASSERT_TRUE(m && m->binary);
    std::string_view chunk;
    const protocol::FrameHeader h = protocol::decode_frame(m->data, &chunk);
    EXPECT_EQ(h.kind, protocol::FrameKind::voxel_slice);
    EXPECT_EQ(h.request_id, 9u);
    payload += chunk;
  }
  EXPECT_EQ(payload.size(), begin["bytes"].get<std::size_t>());
  EXPECT_EQ(ws.reply()["type"], "slice_end");
  const protocol::DecodedSlice d = protocol::decode_slice_payload(payload);
  EXPECT_EQ(d.slice.values, slice(grid, 2, k).values);
  std::size_t inside = 0;
  for (float v : d.slice.values) inside += v != 0;
  EXPECT_GT(inside, 0u);

  // Out of range, an unknown job, a missing axis: clear errors, the connection stays.
  ASSERT_FALSE(ws.send({{"type", "get_slice"}, {"request_id", 10}, {"job_id", id}, {"axis", "z"}, {"index", 1000}}));
  json e = ws.reply();
  EXPECT_EQ(e["error"], "bad_request") << e.dump();
  EXPECT_NE(e["detail"].get<std::string>().find("slice index 1000 is out of range"), std::string::npos) << e.dump();
  ASSERT_FALSE(ws.send({{"type", "get_slice"}, {"request_id", 11}, {"job_id", "nope"}, {"axis", "z"}, {"index", 0}}));
  EXPECT_EQ(ws.reply()["error"], "not_found");
  ASSERT_FALSE(ws.send({{"type", "get_slice"}, {"request_id", 12}, {"job_id", id}, {"index", 0}}));
  EXPECT_EQ(ws.reply()["error"], "bad_request");
  ASSERT_FALSE(ws.send({{"type", "get_slice"},
                        {"request_id", 13},
                        {"job_id", id},
                        {"artifact", "metrics"},
                        {"axis", "x"},
                        {"index", 0}}));
  EXPECT_EQ(ws.reply()["error"], "bad_request");
  EXPECT_TRUE(ws.ping(14));

  // A scalar grid (voxel_distance): its slices come as float32.
  const json dist = wait_end(submit("voxel_distance", {{"resolution", 16}})["id"]);
  ASSERT_EQ(dist["state"], "done") << dist.dump();
  ASSERT_FALSE(ws.send({{"type", "get_slice"},
                        {"request_id", 15},
                        {"job_id", dist["id"]},
                        {"artifact", "distance"},
                        {"axis", "y"},
                        {"index", 8}}));
  // Job events (job_progress, job_done) of that job reach this open socket too.
  auto reply = [&] {
    json m = ws.reply();
    while (m.value("type", "").rfind("job_", 0) == 0) m = ws.reply();
    return m;
  };
  const json fb = reply();
  ASSERT_EQ(fb["type"], "slice") << fb.dump();
  std::string fpayload;
  for (int i = 0; i < fb["chunks"].get<int>(); ++i) {
    auto m = ws.read();
    while (m && !m->binary && json::parse(m->data).value("type", "").rfind("job_", 0) == 0)
      m = ws.read();  // a late job event
    ASSERT_TRUE(m && m->binary);
    std::string_view chunk;
    protocol::decode_frame(m->data, &chunk);
    fpayload += chunk;
  }
  EXPECT_EQ(reply()["type"], "slice_end");
  const protocol::DecodedSlice fd = protocol::decode_slice_payload(fpayload);
  EXPECT_TRUE(fd.floats);
  EXPECT_GT(*std::max_element(fd.slice.values.begin(), fd.slice.values.end()), 0.f);

  // Too large a grid for the memory limit: the job fails with the memory it would need.
  // Over the memory limit: refused at submission (the precheck), naming the size.
  const json big = submit("voxelize", {{"resolution", 4000}}, 400);
  EXPECT_NE(big["detail"].get<std::string>().find("59.7 GB"), std::string::npos) << big.dump();
}

TEST_F(JobsTest, AJobRunsOnAnEarlierJobsOutputMesh) {
  const json first = wait_end(submit("test_translate", json::object())["id"]);
  ASSERT_EQ(first["state"], "done") << first.dump();
  // Named as the viewer names a result; a name that cannot be a mesh's is refused first.
  const json badly = {{"algorithm", "centroid_distance"},
                      {"inputs", {{"mesh", {{"job", first["id"]}, {"artifact", "mesh"}, {"name", "a/b"}}}}}};
  const auto refused = http_call(server_.port(), Method::post, "/api/v1/jobs", badly.dump());
  EXPECT_EQ(refused.status, 400u) << refused.body;
  EXPECT_NE(refused.body.find("'/'"), std::string::npos) << refused.body;
  const json body = {{"algorithm", "centroid_distance"},
                     {"inputs", {{"mesh", {{"job", first["id"]}, {"artifact", "mesh"}, {"name", "box · translate"}}}}},
                     {"params", json::object()}};
  const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs", body.dump());
  ASSERT_EQ(r.status, 201) << r.body;
  const json second = wait_end(r.body_json()["id"]);
  ASSERT_EQ(second["state"], "done") << second.dump();
  // It ran on the translated mesh, stored as a mesh of its own.
  const std::string chained_mesh = second["inputs"]["mesh"];
  EXPECT_NE(chained_mesh, mesh_id_);
  const json m = http_get(server_.port(), "/api/v1/meshes/" + chained_mesh).body_json();
  const json original = http_get(server_.port(), "/api/v1/meshes/" + mesh_id_).body_json();
  EXPECT_EQ(m["name"], "box · translate");
  EXPECT_EQ(m["report"]["vertices"], original["report"]["vertices"]);
  EXPECT_NEAR(m["report"]["bbox"]["min"][0].get<double>(), original["report"]["bbox"]["min"][0].get<double>() + 1.0,
              1e-5);
  // Distances from the centroid do not change under a translation.
  const std::string moved = artifact(second["id"], "distance", "f32");
  const json direct = wait_end(submit("centroid_distance", json::object())["id"]);
  const std::string here = artifact(direct["id"], "distance", "f32");
  ASSERT_EQ(moved.size(), here.size());
  for (std::size_t i = 0; i < here.size() / 4; ++i) {
    float a, b;
    std::memcpy(&a, moved.data() + 4 * i, 4);
    std::memcpy(&b, here.data() + 4 * i, 4);
    EXPECT_NEAR(a, b, 1e-5) << i;
  }
  // An unknown job or artifact as input: 404.
  const json bad = {{"algorithm", "centroid_distance"},
                    {"inputs", {{"mesh", {{"job", "nope"}, {"artifact", "mesh"}}}}}};
  EXPECT_EQ(http_call(server_.port(), Method::post, "/api/v1/jobs", bad.dump()).status, 404);
}

// A mesh as students' scans have it (two boxes on one edge): simplify's
// `repair` is on by default, as the listing says; the job runs on a
// repaired copy and says so in a warning, and the stored mesh is as it was
// uploaded; with repair off the job fails with the precondition.
TEST_F(JobsTest, ANonManifoldMeshIsRepairedFirstWithAWarning) {
  const json list = http_get(server_.port(), "/api/v1/algorithms").body_json();
  for (const char* name : {"simplify", "hausdorff", "sdf_segmentation", "geodesic_distance", "skeleton_mcf"}) {
    const auto it = std::find_if(list["algorithms"].begin(), list["algorithms"].end(),
                                 [&](const json& a) { return a["name"] == name; });
    ASSERT_NE(it, list["algorithms"].end()) << name;
    EXPECT_EQ((*it)["params"]["properties"]["repair"]["default"], true) << name;
  }
  const Mesh boxes = test::two_boxes_sharing_an_edge();
  const fs::path file = dir_ / "boxes.off";
  write_mesh(boxes, file);
  const auto up = http_call(server_.port(), Method::post, "/api/v1/meshes?name=boxes.off", read_bytes(file));
  ASSERT_EQ(up.status, 201) << up.body;
  const std::string id = up.body_json()["id"];
  const json before = http_get(server_.port(), "/api/v1/meshes/" + id).body_json();
  ASSERT_EQ(before["report"]["manifold"], false) << before.dump();
  EXPECT_EQ(before["report"]["non_manifold_edges"], 1) << before.dump();

  auto run = [&](const json& params) {
    const json body = {{"algorithm", "simplify"}, {"inputs", {{"mesh", id}}}, {"params", params}};
    const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs", body.dump());
    EXPECT_EQ(r.status, 201) << r.body;
    return wait_end(r.body_json()["id"]);
  };
  const json done = run(json::object());
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["params"]["repair"], true);
  ASSERT_EQ(done["warnings"].size(), 1u) << done.dump();
  const std::string w = done["warnings"][0];
  EXPECT_EQ(w.rfind("simplify: the mesh was not manifold", 0), 0u) << w;
  EXPECT_NE(w.find("a copy was repaired first: 2 vertices duplicated to split non-manifold edges and vertices"),
            std::string::npos)
      << w;
  EXPECT_EQ(http_get(server_.port(), "/api/v1/meshes/" + id).body_json(), before);

  const json refused = run({{"repair", false}});
  ASSERT_EQ(refused["state"], "failed") << refused.dump();
  EXPECT_NE(refused["error"].get<std::string>().find("simplify needs a manifold mesh"), std::string::npos)
      << refused.dump();
}

// An input of kind points takes a stored cloud, any stored mesh's vertices,
// or an earlier job's points or mesh; an algorithm that needs faces refuses
// a cloud with a 400 that says so.
TEST_F(JobsTest, APointCloudInputFromACloudAMeshOrAnEarlierJob) {
  const auto up = http_call(server_.port(), Method::post, "/api/v1/meshes?name=scan.xyz",
                            "0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n0 0 1 1 0 0\n");
  ASSERT_EQ(up.status, 201) << up.body;
  const std::string cloud = up.body_json()["id"];
  EXPECT_EQ(up.body_json()["points"], true);
  auto run = [&](const json& input) {
    const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs",
                             json{{"algorithm", "test_points"}, {"inputs", {{"points", input}}}}.dump());
    EXPECT_EQ(r.status, 201) << r.body;
    const json done = wait_end(r.body_json()["id"]);
    EXPECT_EQ(done["state"], "done") << done.dump();
    return done;
  };
  const json first = run(cloud);
  json given = json::parse(artifact(first["id"], "given", "json"));
  EXPECT_EQ(given["points"], 4);
  EXPECT_EQ(given["normals"], 1);
  EXPECT_EQ(given["min_x"], 0);
  ASSERT_EQ(first["artifacts"][0]["kind"], "points");
  // Served as a Draco point cloud by default (the viewer's), and as ply and xyz.
  const auto drc = http_get(server_.port(), "/api/v1/jobs/" + first["id"].get<std::string>() + "/artifacts/points");
  ASSERT_EQ(drc.status, 200) << drc.body;
  const Mesh moved = read_mesh_bytes(drc.body, MeshFormat::drc, "points.drc").mesh;
  EXPECT_EQ(moved.num_vertices(), 4u);
  EXPECT_EQ(moved.num_faces(), 0u);
  EXPECT_EQ(moved.normals.size(), 4u);
  EXPECT_EQ(read_mesh_bytes(artifact(first["id"], "points", "xyz"), MeshFormat::xyz, "p.xyz").mesh.num_vertices(), 4u);
  // The earlier job's cloud, moved again.
  given = json::parse(artifact(run({{"job", first["id"]}, {"artifact", "points"}})["id"], "given", "json"));
  EXPECT_EQ(given["points"], 4);
  EXPECT_EQ(given["min_x"], 1);
  // A mesh's vertices: the stored sphere's, and an earlier job's mesh.
  const std::size_t sphere = read_mesh(test::sample("sphere.off")).num_vertices();
  given = json::parse(artifact(run(mesh_id_)["id"], "given", "json"));
  EXPECT_EQ(given["points"], sphere);
  const json translated = wait_end(submit("test_translate", json::object())["id"]);
  given = json::parse(artifact(run({{"job", translated["id"]}, {"artifact", "mesh"}})["id"], "given", "json"));
  EXPECT_EQ(given["points"], sphere);
  // Not a cloud: an earlier job's metrics.
  const auto metrics = http_call(
      server_.port(), Method::post, "/api/v1/jobs",
      json{{"algorithm", "test_points"}, {"inputs", {{"points", {{"job", first["id"]}, {"artifact", "given"}}}}}}
          .dump());
  EXPECT_EQ(metrics.status, 400) << metrics.body;
  EXPECT_NE(metrics.body.find("is a metrics"), std::string::npos) << metrics.body;
  // voxelize takes a cloud as its mesh (surface mode: the voxels holding the points), and says so.
  for (const json& a : http_get(server_.port(), "/api/v1/algorithms").body_json()["algorithms"])
    if (a["name"] == "voxelize") {
      EXPECT_EQ(a["inputs"][0].value("faceless", false), true) << a.dump();
    }
  const auto voxels = http_call(server_.port(), Method::post, "/api/v1/jobs",
                                json{{"algorithm", "voxelize"},
                                     {"inputs", {{"mesh", cloud}}},
                                     {"params", {{"resolution", 8}, {"mode", "surface"}}}}
                                    .dump());
  ASSERT_EQ(voxels.status, 201) << voxels.body;
  const json voxelized = wait_end(voxels.body_json()["id"]);
  EXPECT_EQ(voxelized["state"], "done") << voxelized.dump();
  // An algorithm that needs faces refuses the cloud, saying why.
  const auto faces = http_call(server_.port(), Method::post, "/api/v1/jobs",
                               json{{"algorithm", "test_translate"}, {"inputs", {{"mesh", cloud}}}}.dump());
  EXPECT_EQ(faces.status, 400) << faces.body;
  EXPECT_NE(faces.body.find("input 'mesh' (scan.xyz) is a point cloud of 4 points and no faces: test_translate "
                            "needs a mesh with faces"),
            std::string::npos)
      << faces.body;
}

TEST_F(JobsTest, AJobOfTwoInputsTakesBothAndNamesAMissingOne) {
  // hausdorff between the mesh and its translated copy (an earlier job's output).
  const json moved = wait_end(submit("test_translate", json::object())["id"]);
  ASSERT_EQ(moved["state"], "done") << moved.dump();
  const json body = {{"algorithm", "hausdorff"},
                     {"inputs", {{"mesh", mesh_id_}, {"reference", {{"job", moved["id"]}, {"artifact", "mesh"}}}}}};
  const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs", body.dump());
  ASSERT_EQ(r.status, 201) << r.body;
  const json done = wait_end(r.body_json()["id"]);
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["inputs"]["mesh"], mesh_id_);
  EXPECT_NE(done["inputs"]["reference"], mesh_id_);
  // test_translate moves the mesh by 1 along x.
  const json metrics = json::parse(artifact(done["id"], "metrics", "json"));
  EXPECT_NEAR(metrics["hausdorff"].get<double>(), 1.0, metrics["error_bound"].get<double>() + 1e-6) << metrics.dump();
  // The same inputs the other way round are another job, not the cached one.
  const json swapped = {{"algorithm", "hausdorff"},
                        {"inputs", {{"reference", mesh_id_}, {"mesh", done["inputs"]["reference"]}}}};
  const auto r2 = http_call(server_.port(), Method::post, "/api/v1/jobs", swapped.dump());
  ASSERT_EQ(r2.status, 201) << r2.body;
  EXPECT_FALSE(r2.body_json()["cached"].get<bool>());

  // A missing input, an unknown one, a bad one: 400 naming it; an unknown mesh: 404.
  auto post = [&](const json& inputs) {
    return http_call(server_.port(), Method::post, "/api/v1/jobs",
                     json{{"algorithm", "hausdorff"}, {"inputs", inputs}}.dump());
  };
  auto e = post({{"mesh", mesh_id_}});
  EXPECT_EQ(e.status, 400);
  EXPECT_NE(e.body.find("input 'reference' is missing"), std::string::npos) << e.body;
  e = post({{"mesh", mesh_id_}, {"reference", mesh_id_}, {"other", mesh_id_}});
  EXPECT_EQ(e.status, 400);
  EXPECT_NE(e.body.find("no input 'other' (it takes: mesh, reference)"), std::string::npos) << e.body;
  e = post({{"mesh", mesh_id_}, {"reference", 7}});
  EXPECT_EQ(e.status, 400);
  EXPECT_NE(e.body.find("reference"), std::string::npos) << e.body;
  EXPECT_EQ(post({{"mesh", mesh_id_}, {"reference", "0000000000000000"}}).status, 404);
  // The algorithm lists both inputs.
  const json algos = http_get(server_.port(), "/api/v1/algorithms").body_json();
  for (const auto& a : algos["algorithms"])
    if (a["name"] == "hausdorff") {
      ASSERT_EQ(a["inputs"].size(), 2u) << a.dump();
      EXPECT_EQ(a["inputs"][1]["name"], "reference");
    }
}

TEST_F(JobsTest, AGridFromAnEarlierJobIsTheInputOfTheNext) {
  const json vox = wait_end(submit("voxelize", {{"resolution", 24}})["id"]);
  ASSERT_EQ(vox["state"], "done") << vox.dump();
  const json vox_metrics = json::parse(artifact(vox["id"], "metrics", "json"));
  auto post = [&](const json& inputs, const json& params = json::object()) {
    return http_call(server_.port(), Method::post, "/api/v1/jobs",
                     json{{"algorithm", "grid_surface"}, {"inputs", inputs}, {"params", params}}.dump());
  };
  const auto r = post({{"grid", {{"job", vox["id"]}, {"artifact", "grid"}}}});
  ASSERT_EQ(r.status, 201) << r.body;
  const json done = wait_end(r.body_json()["id"]);
  ASSERT_EQ(done["state"], "done") << done.dump();
  EXPECT_EQ(done["inputs"]["grid"]["job"], vox["id"]);
  // The surface encloses the voxels voxelize counted.
  const json m = json::parse(artifact(done["id"], "metrics", "json"));
  EXPECT_EQ(m["voxels"], vox_metrics["occupied_voxels"]) << m.dump() << vox_metrics.dump();
  const std::string ply = artifact(done["id"], "mesh", "ply");
  EXPECT_NE(ply.find("element face"), std::string::npos);
  // A grid over the memory limit is refused at submission, saying what it would take.
  const json big = submit("voxelize", {{"resolution", 1000}, {"max_memory_mb", 64}}, 400);
  EXPECT_NE(big["detail"].get<std::string>().find("parameter 'resolution'"), std::string::npos) << big.dump();
  EXPECT_NE(big["detail"].get<std::string>().find("over the limit max_memory_mb = 64 MB"), std::string::npos)
      << big.dump();
  // A grid input named by a mesh id, an artifact of another kind, a job that is not there.
  auto e = post({{"grid", mesh_id_}});
  EXPECT_EQ(e.status, 400);
  EXPECT_NE(e.body.find("input 'grid' is a voxel_grid"), std::string::npos) << e.body;
  e = post({{"grid", {{"job", vox["id"]}, {"artifact", "metrics"}}}});
  EXPECT_EQ(e.status, 400);
  EXPECT_NE(e.body.find("is a metrics, not a voxel_grid"), std::string::npos) << e.body;
  EXPECT_EQ(post({{"grid", {{"job", "nope"}, {"artifact", "grid"}}}}).status, 404);
  EXPECT_EQ(post({{"grid", {{"job", vox["id"]}, {"artifact", "nope"}}}}).status, 404);
}

// The SDF and curve skeletons through the server: the SDF's fields; a skeleton made by
// one job, measured by the next, served in every skeleton file format.
TEST_F(JobsTest, SdfAndSkeletonJobs) {
  const json sdf = wait_end(submit("sdf", {{"rays", 16}})["id"]);
  ASSERT_EQ(sdf["state"], "done") << sdf.dump();
  const std::string values = artifact(sdf["id"], "sdf", "txt");
  EXPECT_GT(std::count(values.begin(), values.end(), '\n'), 300);  // sphere.off has 320 faces
  EXPECT_NE(submit("sdf", {{"rays", 0}}, 400)["detail"].get<std::string>().find("'rays'"), std::string::npos);
  EXPECT_NE(submit("sdf_fast", {{"fraction", 2.0}}, 400)["detail"].get<std::string>().find("'fraction'"),
            std::string::npos);

  const json mcf = wait_end(submit("skeleton_mcf", json::object())["id"]);
  ASSERT_EQ(mcf["state"], "done") << mcf.dump();
  const auto r =
      http_call(server_.port(), Method::post, "/api/v1/jobs",
                json{{"algorithm", "skeleton_metrics"},
                     {"inputs", {{"mesh", mesh_id_}, {"skeleton", {{"job", mcf["id"]}, {"artifact", "skeleton"}}}}}}
                    .dump());
  ASSERT_EQ(r.status, 201) << r.body;
  const json measured = wait_end(r.body_json()["id"]);
  ASSERT_EQ(measured["state"], "done") << measured.dump();
  const json m = json::parse(artifact(measured["id"], "metrics", "json"));
  EXPECT_EQ(m["nodes"], json::parse(artifact(mcf["id"], "metrics", "json"))["nodes"]) << m.dump();
  for (const char* format : {"obj", "cg", "json", "polylines"}) {
    const std::string bytes = artifact(mcf["id"], "skeleton", format);
    const std::string name = std::string("s.") + (std::string(format) == "polylines" ? "polylines.txt" : format);
    const Skeleton s = read_skeleton_bytes(bytes, skeleton_format_from_name(name), name);
    EXPECT_EQ(double(s.nodes.size()), m["nodes"].get<double>()) << format;
  }
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + mcf["id"].get<std::string>() + "/artifacts/skeleton?format=stl")
                .status,
            400);

  // A skeleton from another tool, uploaded as data for the mesh: a done
  // job's skeleton like mcf's; a malformed one is refused naming its line.
  const std::string cg = write_skeleton_bytes(
      read_skeleton_bytes(artifact(mcf["id"], "skeleton", "cg"), SkeletonFormat::cg, "s.cg"), SkeletonFormat::cg);
  const auto up = http_call(server_.port(), Method::post, "/api/v1/data?name=mcf.cg&mesh=" + mesh_id_, cg);
  ASSERT_EQ(up.status, 201) << up.body;
  const json attached = up.body_json();
  ASSERT_EQ(attached["state"], "done") << attached.dump();
  EXPECT_EQ(
      double(read_skeleton_bytes(artifact(attached["id"], "skeleton", "cg"), SkeletonFormat::cg, "s.cg").nodes.size()),
      m["nodes"].get<double>());
  const auto bad = http_call(server_.port(), Method::post, "/api/v1/data?name=bad.cg", "v 0 0 0\nv 1 0 0\ne 1 3\n");
  EXPECT_EQ(bad.status, 400) << bad.body;
  EXPECT_NE(bad.body_json().value("detail", "").find("bad.cg: line 3"), std::string::npos) << bad.body;
}

TEST_F(JobsTest, BadRequests) {
  json e = submit("centroid_distance", {{"exponent", 9}}, 400);
  EXPECT_EQ(e["error"], "bad_request");
  EXPECT_EQ(e["detail"], "parameter 'exponent': 9 is over the maximum 4");
  e = submit("centroid_distance", {{"rays", 9}}, 400);
  EXPECT_NE(e["detail"].get<std::string>().find("'rays'"), std::string::npos) << e.dump();
  e = submit("centroid_distance", {{"normalize", "yes"}}, 400);
  EXPECT_NE(e["detail"].get<std::string>().find("'normalize'"), std::string::npos) << e.dump();
  e = submit("no_such_algorithm", json::object(), 404);
  EXPECT_EQ(e["error"], "not_found");
  const auto r = http_call(server_.port(), Method::post, "/api/v1/jobs",
                           json{{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", "0000000000000000"}}}}.dump());
  EXPECT_EQ(r.status, 404);
  EXPECT_EQ(http_call(server_.port(), Method::post, "/api/v1/jobs", "not json").status, 400);
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/0000000000000000").status, 404);
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/0000000000000000").status, 404);
}

// A worker that exits 0 with a result list whose files are cut short (killed
// while writing, or a plugin's bug) fails its job saying which artifact is
// short; it is never done without its results.
TEST_F(JobsTest, TruncatedArtifactsFailTheJobNamingThem) {
  server_.kill_now();
  const fs::path script = dir_ / "truncating-worker";
  test::write_text(script, "#!/bin/sh\n" + test::bin("cgview-worker-test") +
                               " \"$@\"; rc=$?\n[ \"$1\" = --list ] && exit $rc\n"
                               "for f in \"" +
                               std::string(test::kWorkerOutSh) + "\"/*.f32; do truncate -s 7 \"$f\"; done\nexit $rc\n");
  ::chmod(script.c_str(), 0755);
  ASSERT_TRUE(start({"--worker", script.string()}));
  const json j = wait_end(submit("centroid_distance", {{"exponent", 2}})["id"]);
  EXPECT_EQ(j["state"], "failed") << j.dump();
  EXPECT_EQ(j.value("error", ""), "the worker's results are incomplete: artifact 'distance': 7 bytes for 162 values")
      << j.dump();
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + j["id"].get<std::string>() + "/artifacts/distance").status, 400);
}

// A worker wrapped by a shell script that runs BEFORE it, then the worker
// itself (--list passes through).
fs::path wrapped_worker(const fs::path& dir, const std::string& name, const std::string& before) {
  const fs::path script = dir / name;
  const std::string worker = test::bin("cgview-worker-test");
  test::write_text(script, "#!/bin/sh\n[ \"$1\" = --list ] && exec " + worker + " --list\n" + before + "\nexec " +
                               worker + " \"$@\"\n");
  ::chmod(script.c_str(), 0755);
  return script;
}

// A worker that writes anything but progress lines on its progress pipe is
// broken: it is stopped at once and its job fails quoting what it wrote,
// rather than running on with its output ignored.
TEST_F(JobsTest, GarbageOnTheProgressPipeFailsTheJobQuotingIt) {
  server_.kill_now();
  ASSERT_TRUE(
      start({"--worker", wrapped_worker(dir_, "garbling-worker", "echo 'hello from a broken worker'").string()}));
  const auto t0 = Clock::now();
  const json j = wait_end(submit("test_sleep", {{"seconds", 30}})["id"]);
  EXPECT_LT(Clock::now() - t0, 10s) << "stopped at once, not at the end of its 30 s";
  EXPECT_EQ(j["state"], "failed") << j.dump();
  EXPECT_EQ(j.value("error", ""),
            "the worker wrote something other than progress on its progress pipe: \"hello from a broken worker\"");
  EXPECT_EQ(worker_processes(j["id"]), 0);
  EXPECT_TRUE(server_.alive());
}

TEST_F(JobsTest, OutputWithoutALineEndFailsTheJobSayingSo) {
  server_.kill_now();
  // The worker never starts after it (its first progress line would end the
  // line, and the server, reading both at once, saw a line of 70024 bytes).
  ASSERT_TRUE(
      start({"--worker",
             wrapped_worker(dir_, "endless-worker", "head -c 70000 /dev/zero | tr '\\0' x; exec sleep 30").string()}));
  const json j = wait_end(submit("test_sleep", {{"seconds", 30}})["id"]);
  EXPECT_EQ(j["state"], "failed") << j.dump();
  const std::string error = j.value("error", "");
  EXPECT_EQ(error.rfind("the worker wrote something other than progress on its progress pipe: ", 0), 0u) << error;
  EXPECT_NE(error.find(" bytes without a line end"), std::string::npos) << error;
}

// What an algorithm prints to stdout goes to the job's stderr, not to the
// progress pipe: the job is done, and its progress still came.
TEST_F(JobsTest, AnAlgorithmPrintingToStdoutStillSucceeds) {
  const json j = wait_end(submit("test_chatty", json::object())["id"]);
  EXPECT_EQ(j["state"], "done") << j.dump();
  const std::string err = read_bytes(data_ / "jobs" / j["id"].get<std::string>() / "stderr.txt");
  EXPECT_NE(err.find("progress banana"), std::string::npos) << err;
  EXPECT_NE(err.find("a line from std::cout"), std::string::npos) << err;
}

// Any artifact cut short after its worker wrote it (here a mesh, whose
// size no header gives) fails the job naming it, with both sizes.
TEST_F(JobsTest, ATruncatedMeshArtifactFailsTheJobWithItsSizes) {
  server_.kill_now();
  const fs::path script = dir_ / "halving-worker";
  test::write_text(script, "#!/bin/sh\n" + test::bin("cgview-worker-test") +
                               " \"$@\"; rc=$?\n[ \"$1\" = --list ] && exit $rc\n"
                               "for f in \"" +
                               std::string(test::kWorkerOutSh) +
                               "\"/*.ply; do truncate -s \"$(( $(stat -c %s \"$f\") / 2 ))\" \"$f\"; "
                               "done\nexit $rc\n");
  ::chmod(script.c_str(), 0755);
  ASSERT_TRUE(start({"--worker", script.string()}));
  const json j = wait_end(submit("test_translate", json::object())["id"]);
  EXPECT_EQ(j["state"], "failed") << j.dump();
  const std::string error = j.value("error", "");
  std::size_t kept = 0, written = 0;
  ASSERT_EQ(
      std::sscanf(error.c_str(), "the worker's results are incomplete: artifact 'mesh': %zu bytes of the %zu written",
                  &kept, &written),
      2)
      << error;
  EXPECT_GT(written, 1000u);
  EXPECT_EQ(kept, written / 2);
}

TEST_F(JobsTest, CrashMemoryAndTimeLimitsFailAlone) {
  const json crash = submit("test_segfault", json::object());
  const json hog = submit("test_memory_hog", json::object());
  const json slow = submit("test_sleep", {{"seconds", 60}});
  const json c = wait_end(crash["id"]);
  EXPECT_EQ(c["state"], "failed");
  EXPECT_EQ(c["error"], "killed by signal SIGSEGV");
  const json h = wait_end(hog["id"]);
  EXPECT_EQ(h["state"], "failed");
  EXPECT_EQ(h["error"], "exceeded its memory limit of " + std::to_string(kMemoryMb) + " MB");
  const json s = wait_end(slow["id"]);
  EXPECT_EQ(s["state"], "failed");
  EXPECT_EQ(s["error"], "exceeded its time limit of " + std::to_string(kTimeoutS) + " s");
  EXPECT_NE(s["finished"], nullptr);
  // The server still answers, and another job still completes.
  EXPECT_EQ(http_get(server_.port(), "/api/v1/health").status, 200);
  EXPECT_EQ(wait_end(submit("centroid_distance", {{"exponent", 1.5}})["id"])["state"], "done");
  EXPECT_TRUE(server_.alive());
}

TEST_F(JobsTest, CancelARunningJobWithinTwoSeconds) {
  const json job = submit("test_sleep", {{"seconds", 60}});
  const std::string id = job["id"];
  wait_state(id, "running");
  std::this_thread::sleep_for(200ms);
  const auto t0 = Clock::now();
  const auto r = http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + id);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(r.body_json()["state"], "cancelled");
  while (worker_processes(id) > 0 && Clock::now() - t0 < 3s) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(worker_processes(id), 0);
  EXPECT_LT(Clock::now() - t0, 2s);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(get(id)["state"], "cancelled");
  // A queued job cancels too (both workers busy).
  const json a = submit("test_sleep", {{"seconds", 60}}), b = submit("test_sleep", {{"seconds", 61}}),
             queued = submit("test_sleep", {{"seconds", 62}});
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + queued["id"].get<std::string>())
                .body_json()["state"],
            "cancelled");
  http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + a["id"].get<std::string>());
  http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + b["id"].get<std::string>());
}

// A job cancelled while its sandbox is being set up, on a server that dies
// just after: nothing of the job may stay behind (bubblewrap's first process
// in the sandbox waits forever for a parent that is gone).
TEST_F(JobsTest, ACancelledJobLeavesNoProcessEvenWhenTheServerDiesAtOnce) {
  std::vector<std::string> ids;
  // At a few moments after the launch, one of which falls in the set-up.
  for (int k = 0; k < 12; ++k) {
    ids.push_back(submit("test_sleep", {{"seconds", 60}})["id"]);
    std::this_thread::sleep_for(std::chrono::milliseconds(3 * k));
    http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + ids.back());
  }
  server_.kill_now();
  const auto t0 = Clock::now();
  auto left = [&] {
    int n = 0;
    for (const std::string& id : ids) n += worker_processes(id);
    return n;
  };
  while (left() > 0 && Clock::now() - t0 < 5s) std::this_thread::sleep_for(20ms);
  EXPECT_EQ(left(), 0);
}

TEST_F(JobsTest, WebSocketEvents) {
  WsClient ws;
  ASSERT_FALSE(ws.connect(server_.port()));
  const json job = submit("test_sleep", {{"seconds", 0.6}});
  bool progress = false, done = false;
  const auto deadline = Clock::now() + 10s;
  while (!done && Clock::now() < deadline) {
    const auto m = ws.read(10s);
    ASSERT_TRUE(m);
    const json e = json::parse(m->data);
    if (e["type"] == "job_progress" && e["job"]["id"] == job["id"]) progress = true;
    if (e["type"] == "job_done" && e["job"]["id"] == job["id"]) {
      done = true;
      EXPECT_EQ(e["job"]["state"], "done");
      EXPECT_EQ(e["job"]["artifacts"].size(), 1u);
    }
  }
  EXPECT_TRUE(progress);
  EXPECT_TRUE(done);
  const json f = submit("test_segfault", json::object());
  for (;;) {
    const auto m = ws.read(10s);
    ASSERT_TRUE(m);
    const json e = json::parse(m->data);
    if (e["type"] == "job_failed") {
      EXPECT_EQ(e["job"]["id"], f["id"]);
      break;
    }
  }
}

TEST_F(JobsTest, ServerKilledMidJobRunsItAgainAfterRestart) {
  const json finished = submit("centroid_distance", {{"exponent", 0.5}});
  ASSERT_EQ(wait_end(finished["id"])["state"], "done");
  const std::string f32 = artifact(finished["id"], "distance", "f32");
  const json slow = submit("test_sleep", {{"seconds", 1.5}});
  wait_state(slow["id"], "running");
  std::this_thread::sleep_for(300ms);
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(worker_processes(slow["id"]), 0) << "the worker outlived its server";
  EXPECT_EQ(test::integrity_check(data_ / "cgview.db"), "ok");

  ASSERT_TRUE(start());
  EXPECT_EQ(get(finished["id"])["state"], "done");
  EXPECT_EQ(artifact(finished["id"], "distance", "f32"), f32);
  const json again = wait_end(slow["id"]);
  EXPECT_EQ(again["state"], "done") << again.dump();
  EXPECT_EQ(again["artifacts"].size(), 1u);

  // With --on-restart interrupt, a job the server was running is marked interrupted.
  const json slow2 = submit("test_sleep", {{"seconds", 30}});
  wait_state(slow2["id"], "running");
  EXPECT_EQ(server_.stop(SIGKILL), 128 + SIGKILL);
  ASSERT_TRUE(start({"--on-restart", "interrupt"}));
  const json j = get(slow2["id"]);
  EXPECT_EQ(j["state"], "interrupted");
  EXPECT_NE(j["error"], nullptr);
  EXPECT_EQ(get(finished["id"])["state"], "done");
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  EXPECT_EQ(test::integrity_check(data_ / "cgview.db"), "ok");
}

// The files under a directory, in bytes: the test's own count of a job's results.
std::uint64_t bytes_under(const fs::path& dir) {
  std::uint64_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) n += e.file_size();
  return n;
}

TEST_F(JobsTest, AFinishedJobsResultSizeIsStoredWithItAndCountedAfterARestart) {
  auto used = [&] {
    return http_get(server_.port(), "/api/v1/me").body_json()["storage_bytes_used"].get<std::uint64_t>();
  };
  const std::uint64_t meshes = used();
  const json job = submit("centroid_distance", {{"exponent", 0.5}});
  ASSERT_EQ(wait_end(job["id"])["state"], "done");
  const std::string id = job["id"];
  const fs::path results = data_ / "jobs" / id;
  const std::uint64_t size = bytes_under(results);
  ASSERT_GT(size, 0u);
  EXPECT_EQ(used(), meshes + size);
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  const fs::path db = data_ / "cgview.db";
  const std::string size_column = "SELECT bytes FROM jobs WHERE id = '" + id + "'";
  EXPECT_EQ(test::sqlite_query(db, size_column), std::to_string(size));

  // The next start reads the stored size: a file added meanwhile is not walked.
  std::string extra(1000, 'x');
  {
    std::ofstream f(results / "extra.bin", std::ios::binary);
    f << extra;
  }
  ASSERT_TRUE(start());
  EXPECT_EQ(used(), meshes + size);
  EXPECT_EQ(get(id)["state"], "done");
  EXPECT_EQ(server_.stop(SIGTERM), 0);

  // A database from before the column: it loads, sizes the job once from its
  // directory, and stores it.
  EXPECT_EQ(test::sqlite_query(db, "ALTER TABLE jobs DROP COLUMN bytes"), "");
  EXPECT_EQ(test::sqlite_query(db, size_column).rfind("error: no such column", 0), 0u);
  ASSERT_TRUE(start());
  EXPECT_EQ(used(), meshes + size + extra.size());
  EXPECT_EQ(get(id)["state"], "done");
  EXPECT_EQ(artifact(id, "distance", "f32").size(), 4 * 162u) << "one float per vertex of the sphere";
  EXPECT_EQ(server_.stop(SIGTERM), 0);
  EXPECT_EQ(test::sqlite_query(db, size_column), std::to_string(size + extra.size()));
  EXPECT_EQ(test::integrity_check(db), "ok");
}

// DELETE on an ended job removes it and its results: its owner's storage
// is free again.  An identical job answered from the same files (cached)
// keeps them, and is still served.
TEST_F(JobsTest, DeletingAnEndedJobRemovesItsResultsAndFreesItsStorage) {
  auto used = [&] {
    return http_get(server_.port(), "/api/v1/me").body_json()["storage_bytes_used"].get<std::uint64_t>();
  };
  const std::uint64_t meshes = used();
  const json job = submit("centroid_distance", {{"exponent", 0.75}});
  ASSERT_EQ(wait_end(job["id"])["state"], "done");
  const std::string id = job["id"];
  const json twin = submit("centroid_distance", {{"exponent", 0.75}});
  ASSERT_TRUE(twin.value("cached", false)) << twin.dump();
  const std::string field = artifact(id, "distance", "f32");
  ASSERT_EQ(field.size(), 4 * 162u);
  EXPECT_GT(used(), meshes);
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + id).status, 204);
  EXPECT_EQ(http_get(server_.port(), "/api/v1/jobs/" + id).status, 404);
  EXPECT_EQ(artifact(twin["id"], "distance", "f32"), field) << "the cached twin lost its results";
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + twin["id"].get<std::string>()).status, 204);
  EXPECT_FALSE(fs::exists(data_ / "jobs" / id)) << "the results outlived every job that names them";
  EXPECT_EQ(used(), meshes);
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + id).status, 404);
}

// A job after another is run by the worker started ahead of it (in its
// sandbox, its libraries loaded), not by one started for it: that worker
// then is the job's alone, found and ended as any job's worker.
TEST_F(JobsTest, TheWorkerStartedAheadRunsTheNextJobAndIsThatJobsAlone) {
  EXPECT_EQ(wait_end(submit("centroid_distance", {{"exponent", 1.5}})["id"])["state"], "done");
  std::map<pid_t, std::string> ahead;
  for (int i = 0; i < 250 && ahead.empty(); ++i) {
    ahead = test::processes_naming(data_);
    std::erase_if(ahead, [](const auto& p) { return p.second.find(test::kPrestartedWorker) == std::string::npos; });
    if (ahead.empty()) std::this_thread::sleep_for(20ms);
  }
  ASSERT_FALSE(ahead.empty()) << "no worker was started ahead of the next job";
  // Ready once the worker itself waits on its stdin pipe (a job before
  // that gets a worker of its own).
  auto waiting = [&] {
    for (const auto& e : fs::directory_iterator("/proc")) {
      std::error_code ec;
      const std::string exe = fs::read_symlink(e.path() / "exe", ec).string();
      const std::string err = fs::read_symlink(e.path() / "fd" / "2", ec).string();
      if (exe.ends_with("cgview-worker-test") && err.find("/runs/warm-") != std::string::npos &&
          read_bytes(e.path() / "wchan").find("pipe_read") != std::string::npos)
        return true;
    }
    return false;
  };
  for (int i = 0; i < 250 && !waiting(); ++i) std::this_thread::sleep_for(20ms);
  ASSERT_TRUE(waiting()) << "the worker started ahead never waited for its job";
  const std::string id = submit("test_sleep", {{"seconds", 30}})["id"];
  wait_state(id, "running");
  const std::set<pid_t> runs = worker_pids(id);
  EXPECT_TRUE(std::any_of(runs.begin(), runs.end(), [&](pid_t p) { return ahead.count(p) > 0; }))
      << "the job's workers are not the one started ahead of it";
  EXPECT_EQ(http_call(server_.port(), Method::delete_, "/api/v1/jobs/" + id).status, 200);
  EXPECT_EQ(wait_end(id)["state"], "cancelled");
  const auto t0 = Clock::now();
  while (worker_processes(id) > 0 && Clock::now() - t0 < 3s) std::this_thread::sleep_for(10ms);
  EXPECT_EQ(worker_processes(id), 0);
  // The job after it is done too.
  const json j = wait_end(submit("centroid_distance", {{"exponent", 2.5}})["id"]);
  EXPECT_EQ(j["state"], "done") << j.dump();
}

}  // namespace
}  // namespace cgview
