// GET /api/v1/meshes/{id}/render.png on the real cgview-server: a PNG of the
// asked size, a scalar-field artifact as colours, 400s naming the bad
// parameter, concurrent requests, and the route in openapi.json.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "render/image.h"
#include "server_harness.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using test::http_call;
using test::http_get;
using test::Method;
using test::read_bytes;
using test::ServerProcess;
using test::wait_job_end;

class RenderEndpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::temp_dir("render_endpoint");
    ASSERT_TRUE(server_.start(dir_ / "data", {"--worker", test::bin("cgview-worker"), "--job-workers", "1"}, dir_));
    const auto r = http_call(server_.port(), Method::post, "/api/v1/meshes?name=elephant.off",
                             read_bytes(test::sample("elephant.off")));
    ASSERT_EQ(r.status, 201u) << r.body;
    mesh_ = r.body_json()["id"];
  }
  void TearDown() override {
    server_.kill_now();
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string target(const std::string& query) const { return "/api/v1/meshes/" + mesh_ + "/render.png" + query; }

  // A 400 whose JSON names `parameter`.
  void expect_bad(const std::string& query, const std::string& parameter) {
    const auto r = http_get(server_.port(), target(query));
    EXPECT_EQ(r.status, 400u) << query << ": " << r.body;
    const json body = r.body_json();
    EXPECT_EQ(body.value("parameter", ""), parameter) << query << ": " << r.body;
    EXPECT_NE(body.value("detail", "").find(parameter), std::string::npos) << r.body;
  }

  fs::path dir_;
  ServerProcess server_;
  std::string mesh_;
};

TEST_F(RenderEndpointTest, ServesAPngOfTheAskedSize) {
  const auto r = http_get(server_.port(), target("?width=96&height=64&mode=flat&azimuth=90&elevation=10"));
  ASSERT_EQ(r.status, 200u) << r.body;
  EXPECT_EQ(r.header("content-type"), "image/png");
  const render::Image im = render::decode_png(r.body);
  EXPECT_EQ(im.width, 96);
  EXPECT_EQ(im.height, 64);
  long drawn = 0;
  for (std::size_t i = 0; i < im.rgba.size(); i += 4) drawn += im.rgba[i] != 255 || im.rgba[i + 1] != 255;
  EXPECT_GT(drawn, 200);
  // Every mode.
  for (const char* mode : {"points", "wireframe", "smooth", "toon"})
    EXPECT_EQ(http_get(server_.port(), target("?width=32&height=32&mode=" + std::string(mode))).status, 200u) << mode;
  // A missing mesh is 404.
  EXPECT_EQ(http_get(server_.port(), "/api/v1/meshes/nope/render.png").status, 404u);
}

TEST_F(RenderEndpointTest, BadParametersAre400NamingThem) {
  expect_bad("?width=0", "width");
  expect_bad("?width=8193", "width");
  expect_bad("?height=0", "height");
  expect_bad("?height=abc", "height");
  expect_bad("?width=12.5", "width");
  expect_bad("?mode=phong", "mode");
  expect_bad("?elevation=120", "elevation");
  expect_bad("?azimuth=north", "azimuth");
  expect_bad("?projection=fisheye", "projection");
  expect_bad("?field=nothing", "field");
  expect_bad("?field=nojob/distance", "field");
  expect_bad("?colour=red", "colour");
}

TEST_F(RenderEndpointTest, ColoursByAScalarFieldArtifact) {
  const json body = {{"algorithm", "centroid_distance"}, {"inputs", {{"mesh", mesh_}}}, {"params", json::object()}};
  const auto sub = http_call(server_.port(), Method::post, "/api/v1/jobs", body.dump());
  ASSERT_EQ(sub.status, 201u) << sub.body;
  const std::string job = sub.body_json()["id"];
  ASSERT_EQ(wait_job_end(server_.port(), job).value("state", ""), "done");
  const auto plain = http_get(server_.port(), target("?width=80&height=80"));
  const auto by_id = http_get(server_.port(), target("?width=80&height=80&field=" + job + "/distance"));
  const auto by_name = http_get(server_.port(), target("?width=80&height=80&field=distance"));
  ASSERT_EQ(plain.status, 200u);
  ASSERT_EQ(by_id.status, 200u) << by_id.body;
  ASSERT_EQ(by_name.status, 200u) << by_name.body;
  EXPECT_EQ(by_id.body, by_name.body);
  const render::Image a = render::decode_png(plain.body), b = render::decode_png(by_id.body);
  long differ = 0;
  for (std::size_t i = 0; i < a.rgba.size(); ++i) differ += a.rgba[i] != b.rgba[i];
  EXPECT_GT(differ, 500);
  expect_bad("?field=" + job + "/nothing", "field");
}

TEST_F(RenderEndpointTest, ConcurrentRequestsAgree) {
  const std::string reference = http_get(server_.port(), target("?width=64&height=64")).body;
  ASSERT_FALSE(reference.empty());
  std::atomic<int> ok{0}, same{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 6; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 4; ++i) {
        const auto r = http_get(server_.port(), target("?width=64&height=64"));
        ok += r.status == 200;
        same += r.body == reference;
      }
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(ok.load(), 24);
  EXPECT_EQ(same.load(), 24);
  // The server stays responsive and small after many renders.
  const long before = server_.rss_kb();
  for (int i = 0; i < 100; ++i)
    ASSERT_EQ(http_get(server_.port(), target("?width=96&height=96&azimuth=" + std::to_string(i))).status, 200u);
  const long after = server_.rss_kb();
  EXPECT_LT(after - before, 20 * 1024) << before << " kB -> " << after << " kB";
}

TEST_F(RenderEndpointTest, OpenApiListsTheRoute) {
  const json doc = http_get(server_.port(), "/api/v1/openapi.json").body_json();
  ASSERT_TRUE(doc["paths"].contains("/api/v1/meshes/{id}/render.png")) << doc["paths"].dump();
  const json& op = doc["paths"]["/api/v1/meshes/{id}/render.png"]["get"];
  std::vector<std::string> names;
  for (const auto& p : op["parameters"]) names.push_back(p["name"]);
  for (const char* n : {"id", "mode", "width", "height", "azimuth", "elevation", "field"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
}

}  // namespace
}  // namespace cgview
