// POST /api/v1/data on the real server: voxel grids, skeletons and scalar
// fields made by other tools become done jobs' artifacts that download in
// their kinds' formats (read back by the readers that own them), render,
// and feed jobs; bad files are 4xx naming what was wrong, and nothing is kept.
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

#include "core/skeleton.h"
#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "server_harness.h"
#include "test_support.h"
#include "voxel/voxel_io.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;

VoxelGrid ball(int n) {
  VoxelGrid g({n, n, n}, {-1, -1, -1}, 2.0 / n, VoxelType::bit);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        if (std::hypot(i + 0.5 - n / 2.0, j + 0.5 - n / 2.0, k + 0.5 - n / 2.0) < n * 0.4) g.set({i, j, k}, 1);
  return g;
}

class DataUpload : public ServerFixture {
 protected:
  DataUpload() : ServerFixture("data-upload-") {}
  void SetUp() override {
    ServerFixture::SetUp();
    ASSERT_TRUE(server_.start(data_, {}, dir_));
    const HttpResult r =
        http_call(port(), Method::post, "/api/v1/meshes?name=sphere.off", read_bytes(sample("sphere.off")));
    ASSERT_EQ(r.status, 201) << r.body;
    mesh_ = r.body_json();
  }
  HttpResult upload(const std::string& query, const std::string& bytes) {
    return http_call(port(), Method::post, "/api/v1/data?" + query, bytes, 60s);
  }
  json jobs() { return http_get(port(), "/api/v1/jobs").body_json()["jobs"]; }
  std::string artifact(const json& job, const std::string& format) {
    const HttpResult r = http_get(port(), "/api/v1/jobs/" + job["id"].get<std::string>() + "/artifacts/" +
                                              job["artifacts"][0]["name"].get<std::string>() + "?format=" + format);
    EXPECT_EQ(r.status, 200) << format << ": " << r.body;
    return r.body;
  }
  json wait_end(const std::string& id) { return wait_job_end(port(), id, 30s); }
  std::size_t vertices() const { return mesh_["report"]["vertices"].get<std::size_t>(); }
  std::size_t faces() const { return mesh_["report"]["faces"].get<std::size_t>(); }
  json mesh_;
};

TEST_F(DataUpload, AVoxelGridFromAnotherToolIsADoneJobsArtifactThatFeedsAJob) {
  const VoxelGrid grid = ball(20);
  const HttpResult r = upload("name=ball.vti", encode_vti(grid));
  ASSERT_EQ(r.status, 201) << r.body;
  const json job = r.body_json();
  EXPECT_EQ(job["state"], "done");
  EXPECT_EQ(job["algorithm"], "import");
  EXPECT_EQ(job["params"]["file"], "ball.vti");
  ASSERT_EQ(job["artifacts"].size(), 1u);
  EXPECT_EQ(job["artifacts"][0]["name"], "grid");
  EXPECT_EQ(job["artifacts"][0]["kind"], "voxel_grid");
  EXPECT_EQ(job["artifacts"][0]["formats"], json({"nrrd", "binvox", "vti", "vox", "vdb", "vtk"}));
  // Stored as the codec stores a job's grid (NRRD), read back as any tool would.
  const VoxelGrid nrrd = decode_nrrd(artifact(job, "nrrd"));
  EXPECT_EQ(nrrd.dims(), grid.dims());
  EXPECT_EQ(nrrd.count_occupied(), grid.count_occupied());
  EXPECT_EQ(decode_binvox(artifact(job, "binvox")).count_occupied(), grid.count_occupied());
  // An input of the next job, as a job's grid is.
  const json body = {{"algorithm", "grid_surface"},
                     {"inputs", {{"grid", {{"job", job["id"]}, {"artifact", "grid"}}}}},
                     {"params", json::object()}};
  const HttpResult s = http_call(port(), Method::post, "/api/v1/jobs", body.dump());
  ASSERT_EQ(s.status, 201) << s.body;
  const json surface = wait_end(s.body_json()["id"]);
  ASSERT_EQ(surface["state"], "done") << surface.dump();
  const std::string ply = http_get(port(), "/api/v1/jobs/" + surface["id"].get<std::string>() + "/artifacts/" +
                                               surface["artifacts"][0]["name"].get<std::string>())
                              .body;
  EXPECT_GT(read_mesh_bytes(ply, MeshFormat::ply, "surface.ply").mesh.num_faces(), 100u);
  // Listed with the caller's jobs.
  bool listed = false;
  for (const json& j : jobs()) listed |= j["id"] == job["id"];
  EXPECT_TRUE(listed);
}

TEST_F(DataUpload, ASkeletonKeepsItsGraphInEveryFormat) {
  Skeleton s;
  s.nodes = {{0, 0, 0}, {0, 0, 1}, {1, 0, 2}, {-1, 0, 2}, {0, 0, -1}};
  s.edges = {{0, 1}, {1, 2}, {1, 3}, {0, 4}};
  const HttpResult r =
      upload("name=tree.cg&mesh=" + mesh_["id"].get<std::string>(), write_skeleton_bytes(s, SkeletonFormat::cg));
  ASSERT_EQ(r.status, 201) << r.body;
  const json job = r.body_json();
  EXPECT_EQ(job["artifacts"][0]["kind"], "skeleton");
  EXPECT_EQ(job["inputs"]["mesh"], mesh_["id"]) << "shown with the mesh it was uploaded for";
  for (const char* f : {"obj", "cg", "json", "polylines"}) {
    const std::string file = std::string("s.") + (std::string(f) == "polylines" ? "polylines.txt" : f);
    const Skeleton back = read_skeleton_bytes(artifact(job, f), skeleton_format_from_name(file), file);
    EXPECT_EQ(back.num_nodes(), s.num_nodes()) << f;
    EXPECT_EQ(back.num_edges(), s.num_edges()) << f;
  }
}

TEST_F(DataUpload, AFieldAsTextTakesItsLocationFromTheCountAndRenders) {
  std::string text;
  for (std::size_t f = 0; f < faces(); ++f) text += f == 3 ? "nan\n" : std::to_string(double(f) / 10) + "\n";
  const HttpResult r = upload("name=wear.txt&mesh=" + mesh_["id"].get<std::string>(), text);
  ASSERT_EQ(r.status, 201) << r.body;
  const json job = r.body_json();
  const json& a = job["artifacts"][0];
  EXPECT_EQ(a["kind"], "scalar_field");
  EXPECT_EQ(a["name"], "wear");
  EXPECT_EQ(a["location"], "face");
  EXPECT_EQ(a["count"], faces());
  ASSERT_EQ(job["warnings"].size(), 1u) << job.dump();
  EXPECT_EQ(job["warnings"][0],
            "1 of the " + std::to_string(faces()) + " values are missing (nan): those faces show no colour");
  const json values = json::parse(artifact(job, "json"))["values"];
  ASSERT_EQ(values.size(), faces());
  EXPECT_TRUE(values[3].is_null());
  EXPECT_FLOAT_EQ(values[7].get<float>(), 0.7f);
  // The mesh renders coloured by it, as by a job's field.
  const HttpResult png =
      http_get(port(), "/api/v1/meshes/" + mesh_["id"].get<std::string>() +
                           "/render.png?width=64&height=64&field=" + job["id"].get<std::string>() + "/wear");
  EXPECT_EQ(png.status, 200) << png.body;
  EXPECT_EQ(png.body.substr(1, 3), "PNG");
}

TEST_F(DataUpload, AFieldFromAPlyPropertySaysWhatItDidNotUse) {
  // A PLY written by another tool: the sphere with two per-vertex properties.
  const Mesh sphere = read_mesh(sample("sphere.off"));
  std::string ply = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(sphere.num_vertices()) +
                    "\nproperty float x\nproperty float y\nproperty float z\nproperty float quality\n"
                    "property float height\nelement face " +
                    std::to_string(sphere.num_faces()) + "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const Vec3& p : sphere.positions)
    ply += std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + " 1 " + std::to_string(p.z) +
           "\n";
  for (const Tri& t : sphere.faces)
    ply += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  const std::string id = mesh_["id"].get<std::string>();
  const HttpResult r = upload("name=scan.ply&property=height&mesh=" + id, ply);
  ASSERT_EQ(r.status, 201) << r.body;
  const json job = r.body_json();
  EXPECT_EQ(job["artifacts"][0]["name"], "height");
  EXPECT_EQ(job["artifacts"][0]["location"], "vertex");
  EXPECT_EQ(job["warnings"],
            json({"the file's other properties were not used: quality (upload it again with ?property=NAME for one "
                  "of them)",
                  "the file's own vertices and faces were not used: the field is shown on the stored mesh"}));
  const json values = json::parse(artifact(job, "json"))["values"];
  ASSERT_EQ(values.size(), sphere.num_vertices());
  for (std::size_t v = 0; v < sphere.num_vertices(); v += 17)
    EXPECT_NEAR(values[v].get<double>(), sphere.positions[v].z, 1e-5) << v;
  const HttpResult none = upload("name=scan.ply&property=sdf&mesh=" + id, ply);
  expect_error(none, 400, "invalid_mesh");
  EXPECT_NE(none.body.find("has no property 'sdf' (it has quality, height)"), std::string::npos) << none.body;
}

TEST_F(DataUpload, BadUploadsAre4xxSayingWhyAndKeepNothing) {
  const std::string id = mesh_["id"].get<std::string>();
  const std::size_t before = jobs().size();
  struct Case {
    std::string query, bytes;
    unsigned status;
    std::string says;
  } cases[] = {
      {"name=wear.txt&mesh=" + id, "1\n2\n3\n", 400,
       "wear.txt: 3 values, but the mesh has " + std::to_string(vertices()) + " vertices and " +
           std::to_string(faces()) + " faces (one value per vertex, or per face)"},
      {"name=wear.txt", "1\n", 400, "a scalar field is uploaded for a stored mesh: add ?mesh=ID"},
      {"name=wear.txt&mesh=" + id, "1\nmany\n", 400, "wear.txt: line 2: 'many' is not a number"},
      {"name=grid.raw", "\x01\x02", 400, "a .raw grid needs its .json beside it"},
      {"name=notes.docx", "x", 400, "'notes.docx' is no kind of data this server reads"},
      {"name=ball.nrrd", "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 100000\nencoding: raw\n\n", 400,
       "ball.nrrd"},
      {"name=tree.cg", "# D:3 NV:2 NE:1\nv 0 0 0\nv 1 0 0\ne 1 3\n", 400, "tree.cg: line 4"},
      {"name=wear.txt&mesh=0123456789abcdef", "1\n", 404, ""},
      {"name=ball.nrrd&kind=skeleton", "x", 400, "a skeleton is not read from 'ball.nrrd'"},
      {"kind=skeleton", "x", 400, "the query needs ?name=FILE.EXT"},
  };
  for (const Case& c : cases) {
    const HttpResult r = upload(c.query, c.bytes);
    EXPECT_EQ(r.status, c.status) << c.query << ": " << r.body;
    EXPECT_NE(r.body_json().value("detail", "").find(c.says), std::string::npos)
        << c.query << " should say '" << c.says << "': " << r.body;
  }
  EXPECT_EQ(jobs().size(), before) << "a refused upload keeps no job";
  // Nothing half-written is left in the job directories either.
  std::size_t dirs = 0;
  for (const auto& e : fs::directory_iterator(data_ / "jobs")) dirs += e.is_directory();
  EXPECT_EQ(dirs, before);
  expect_healthy();
}

}  // namespace
}  // namespace cgview::test
