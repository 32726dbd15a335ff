// The HTTP router called directly (no sockets): every REST route, its error
// responses, static files, and the OpenAPI document covering every route.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "mesh_service.h"
#include "router.h"
#include "router_harness.h"
#include "store.h"
#include "test_support.h"

namespace cgview::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

using test::read_bytes;

std::string header(const HttpResponse& r, const std::string& name) {
  for (const auto& [k, v] : r.headers)
    if (k == name) return v;
  return "";
}

// Checks an error response's status and {"error","detail"} body; returns the body.
json expect_error(const HttpResponse& r, int status, const std::string& code) {
  EXPECT_EQ(r.status, status) << r.body;
  EXPECT_EQ(r.content_type, "application/json");
  json j = json::parse(r.body, nullptr, false);
  EXPECT_TRUE(j.is_object()) << r.body;
  if (!j.is_object()) return json::object();
  EXPECT_EQ(j.value("error", ""), code) << r.body;
  EXPECT_TRUE(j.contains("detail") && j["detail"].is_string() && !j["detail"].get<std::string>().empty()) << r.body;
  return j;
}

class RouterTest : public test::RouterFixture {
 protected:
  void SetUp() override {
    make_dir("router-");
    static_dir_ = dir_ / "static";
    fs::create_directories(static_dir_ / "assets");
    test::write_text(static_dir_ / "index.html", "<!doctype html><title>CGView</title>");
    test::write_text(static_dir_ / "assets" / "app.js", "console.log('cgview')");
    open(dir_ / "data", std::nullopt, RouterConfig{static_dir_, "0.1.0"});
    router_->on_event = [this](const json& e, const Access&) { events_.push_back(e); };
  }

  HttpResponse call(const std::string& method, const std::string& target, std::string body = "") {
    return router_->handle({method, target, std::move(body), ""});
  }

  // Uploads a sample; returns the Mesh object.
  json upload_sample(const std::string& file) {
    const HttpResponse r = call("POST", "/api/v1/meshes?name=" + file, read_bytes(test::sample(file)));
    EXPECT_EQ(r.status, 201) << r.body;
    return json::parse(r.body);
  }

  fs::path static_dir_;
  std::vector<json> events_;
};

TEST_F(RouterTest, Health) {
  const HttpResponse r = call("GET", "/api/v1/health");
  ASSERT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "application/json");
  const json j = json::parse(r.body);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_EQ(j["version"], "0.1.0");
  EXPECT_EQ(j["meshes"], 0);
  EXPECT_TRUE(j["uptime_s"].is_number());
  EXPECT_GE(j["uptime_s"].get<double>(), 0.0);
  upload_sample("elephant.off");
  EXPECT_EQ(json::parse(call("GET", "/api/v1/health").body)["meshes"], 1);
}

TEST_F(RouterTest, UploadListGetDelete) {
  const std::string bytes = read_bytes(test::sample("elephant.off"));
  const HttpResponse up = call("POST", "/api/v1/meshes?name=elephant.off", bytes);
  ASSERT_EQ(up.status, 201) << up.body;
  const json mesh = json::parse(up.body);
  const std::string id = mesh["id"];
  EXPECT_EQ(header(up, "Location"), "/api/v1/meshes/" + id);
  EXPECT_EQ(mesh["name"], "elephant.off");
  EXPECT_EQ(mesh["format"], "off");
  EXPECT_EQ(mesh["bytes"], bytes.size());
  EXPECT_EQ(mesh["sha256"], sha256_hex(bytes));
  EXPECT_TRUE(mesh["created"].is_string());
  EXPECT_EQ(mesh["report"]["vertices"], 2775);
  EXPECT_EQ(mesh["report"]["faces"], 5558);
  EXPECT_EQ(mesh["report"]["edges"], 8337);
  EXPECT_TRUE(mesh["warnings"].is_array());
  ASSERT_EQ(events_.size(), 1u);
  EXPECT_EQ(events_[0]["type"], "mesh_added");
  EXPECT_EQ(events_[0]["mesh"], mesh);

  const json second = upload_sample("sphere.off");
  const HttpResponse list = call("GET", "/api/v1/meshes");
  ASSERT_EQ(list.status, 200);
  const json meshes = json::parse(list.body)["meshes"];
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_EQ(meshes[0], mesh);  // newest last
  EXPECT_EQ(meshes[1], second);

  const HttpResponse got = call("GET", "/api/v1/meshes/" + id);
  ASSERT_EQ(got.status, 200);
  EXPECT_EQ(json::parse(got.body), mesh);

  const HttpResponse del = call("DELETE", "/api/v1/meshes/" + id);
  EXPECT_EQ(del.status, 204);
  EXPECT_TRUE(del.body.empty());
  ASSERT_EQ(events_.size(), 3u);
  EXPECT_EQ(events_[2], (json{{"type", "mesh_deleted"}, {"mesh_id", id}}));
  expect_error(call("GET", "/api/v1/meshes/" + id), 404, "not_found");
  expect_error(call("DELETE", "/api/v1/meshes/" + id), 404, "not_found");
  expect_error(call("GET", "/api/v1/meshes/" + id + "/download?format=obj"), 404, "not_found");
  EXPECT_EQ(json::parse(call("GET", "/api/v1/meshes").body)["meshes"].size(), 1u);
}

TEST_F(RouterTest, UploadNameAndFormatFromTheQuery) {
  const std::string bytes = read_bytes(test::sample("sphere.off"));
  const HttpResponse r = call("POST", "/api/v1/meshes?name=my%20ball+1.dat&format=off", bytes);
  ASSERT_EQ(r.status, 201) << r.body;
  const json j = json::parse(r.body);
  EXPECT_EQ(j["name"], "my ball 1.dat");
  EXPECT_EQ(j["format"], "off");
  const HttpResponse d = call("GET", "/api/v1/meshes/" + j["id"].get<std::string>() + "/download");
  EXPECT_EQ(d.status, 200);
  EXPECT_EQ(d.body, bytes);  // the uploaded format: the bytes as uploaded
  EXPECT_EQ(header(d, "Content-Disposition"), "attachment; filename=\"my ball 1.off\"");
}

TEST_F(RouterTest, DownloadInEveryWritableFormat) {
  const json mesh = upload_sample("elephant.off");
  const std::string id = mesh["id"];
  struct Case {
    std::string format, content_type;
  };
  for (const Case& c :
       {Case{"off", "application/octet-stream"}, Case{"obj", "model/obj"}, Case{"ply", "application/octet-stream"},
        Case{"stl", "model/stl"}, Case{"glb", "model/gltf-binary"}, Case{"drc", "application/octet-stream"}}) {
    SCOPED_TRACE(c.format);
    const HttpResponse r = call("GET", "/api/v1/meshes/" + id + "/download?format=" + c.format);
    ASSERT_EQ(r.status, 200) << r.body.substr(0, 200);
    EXPECT_EQ(r.content_type, c.content_type);
    EXPECT_EQ(header(r, "Content-Disposition"), "attachment; filename=\"elephant." + c.format + "\"");
    ASSERT_FALSE(r.body.empty());
    Mesh m;
    if (c.format == "drc") {
      // Decoded by Draco's own tool, not by our reader.
      EXPECT_EQ(r.body.substr(0, 5), "DRACO");
      const fs::path drc = dir_ / "download.drc", obj = dir_ / "download.obj";
      test::write_text(drc, r.body);
      std::string out;
      ASSERT_EQ(test::run("draco_decoder -i '" + drc.string() + "' -o '" + obj.string() + "'", &out), 0) << out;
      m = read_mesh(obj);
    } else {
      m = read_mesh_bytes(r.body, format_from_name("x." + c.format), "download." + c.format).mesh;
    }
    EXPECT_EQ(m.num_vertices(), 2775u);
    EXPECT_EQ(m.num_faces(), 5558u);
  }
}

TEST_F(RouterTest, UnknownIdsAre404) {
  expect_error(call("GET", "/api/v1/meshes/0123456789abcdef"), 404, "not_found");
  expect_error(call("DELETE", "/api/v1/meshes/0123456789abcdef"), 404, "not_found");
  expect_error(call("GET", "/api/v1/meshes/nope/download?format=obj"), 404, "not_found");
  expect_error(call("GET", "/api/v1/nothing"), 404, "not_found");
  expect_error(call("GET", "/api/v1/meshes/a/b/c"), 404, "not_found");
}

TEST_F(RouterTest, BadFormatsAre400) {
  const std::string id = upload_sample("sphere.off")["id"];
  expect_error(call("GET", "/api/v1/meshes/" + id + "/download?format=las"), 400, "unsupported_format");
  expect_error(call("GET", "/api/v1/meshes/" + id + "/download?format=gltf"), 400, "unsupported_format");
  expect_error(call("GET", "/api/v1/meshes/" + id + "/download?format="), 400, "unsupported_format");
  expect_error(call("POST", "/api/v1/meshes?name=a.las", "whatever"), 400, "unsupported_format");
  expect_error(call("POST", "/api/v1/meshes?name=a.off&format=doc", "whatever"), 400, "unsupported_format");
  EXPECT_EQ(store_->count(), 1u);
}

TEST_F(RouterTest, MalformedFileIs400WithTheParsersMessage) {
  const std::string bad = "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 9\n";
  std::string parser_message;
  try {
    read_mesh_bytes(bad, MeshFormat::off, "broken.off");
    FAIL() << "the reader accepted a face with vertex 9 of 4";
  } catch (const InvalidInput& e) {
    parser_message = e.what();
  }
  const json j = expect_error(call("POST", "/api/v1/meshes?name=broken.off", bad), 400, "invalid_mesh");
  EXPECT_EQ(j["detail"], parser_message);
  EXPECT_NE(parser_message.find("broken.off"), std::string::npos) << parser_message;

  // Truncated binary and an empty body.
  const std::string ply = write_mesh_bytes(test::box(), MeshFormat::ply);
  expect_error(call("POST", "/api/v1/meshes?name=cut.ply", ply.substr(0, ply.size() - 10)), 400, "invalid_mesh");
  expect_error(call("POST", "/api/v1/meshes?name=empty.off", ""), 400, "invalid_mesh");
  const json nothing = expect_error(call("POST", "/api/v1/meshes?name=none.off", "OFF\n0 0 0\n"), 400, "invalid_mesh");
  EXPECT_EQ(nothing["detail"], "none.off is empty: it has no vertices and no faces");
  EXPECT_EQ(store_->count(), 0u);
  EXPECT_TRUE(events_.empty());
}

// A file of points and no faces is a point cloud: stored as a mesh with no
// faces, and its JSON and report say so.
TEST_F(RouterTest, APointCloudIsStoredAndSaidToBeOne) {
  const HttpResponse obj = call("POST", "/api/v1/meshes?name=scan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n");
  ASSERT_EQ(obj.status, 201) << obj.body;
  const json j = json::parse(call("GET", "/api/v1/meshes/" + json::parse(obj.body)["id"].get<std::string>()).body);
  EXPECT_EQ(j["points"], true);
  EXPECT_EQ(j["report"]["points"], true);
  EXPECT_EQ(j["report"]["vertices"], 4);
  EXPECT_EQ(j["report"]["faces"], 0);
  const HttpResponse xyz = call("POST", "/api/v1/meshes?name=scan.xyz", "0 0 0\n1 2 3\n");
  ASSERT_EQ(xyz.status, 201) << xyz.body;
  EXPECT_EQ(json::parse(xyz.body)["points"], true);
  const HttpResponse box = call("POST", "/api/v1/meshes?name=box.ply", write_mesh_bytes(test::box(), MeshFormat::ply));
  EXPECT_EQ(json::parse(box.body)["points"], false);
  EXPECT_EQ(json::parse(box.body)["report"]["points"], false);
}

TEST_F(RouterTest, MissingOrBadNameIs400) {
  const std::string bytes = read_bytes(test::sample("sphere.off"));
  expect_error(call("POST", "/api/v1/meshes", bytes), 400, "bad_request");
  expect_error(call("POST", "/api/v1/meshes?format=off", bytes), 400, "bad_request");
  expect_error(call("POST", "/api/v1/meshes?name=", bytes), 400, "invalid_mesh");
  expect_error(call("POST", "/api/v1/meshes?name=a%2Fb.off", bytes), 400, "invalid_mesh");
  EXPECT_EQ(store_->count(), 0u);
}

TEST_F(RouterTest, WrongMethodIs405) {
  expect_error(call("PUT", "/api/v1/meshes"), 405, "method_not_allowed");
  expect_error(call("POST", "/api/v1/health"), 405, "method_not_allowed");
  expect_error(call("DELETE", "/api/v1/meshes"), 405, "method_not_allowed");
  expect_error(call("PATCH", "/api/v1/meshes/0123456789abcdef"), 405, "method_not_allowed");
  expect_error(call("POST", "/api/v1/openapi.json"), 405, "method_not_allowed");
  expect_error(call("POST", "/index.html"), 405, "method_not_allowed");
}

TEST_F(RouterTest, ServesStaticFiles) {
  const HttpResponse index = call("GET", "/");
  ASSERT_EQ(index.status, 200);
  EXPECT_EQ(index.body, "<!doctype html><title>CGView</title>");
  EXPECT_EQ(index.content_type, "text/html; charset=utf-8");
  EXPECT_EQ(call("GET", "/index.html").body, index.body);
  const HttpResponse js = call("GET", "/assets/app.js");
  ASSERT_EQ(js.status, 200);
  EXPECT_EQ(js.body, "console.log('cgview')");
  EXPECT_EQ(js.content_type, "text/javascript");
  EXPECT_NE(header(js, "Cache-Control").find("immutable"), std::string::npos);
  EXPECT_EQ(call("GET", "/assets/app.js?v=1").status, 200);
  expect_error(call("GET", "/missing.html"), 404, "not_found");
}

TEST_F(RouterTest, RefusesPathTraversal) {
  // A secret next to the static dir: reachable by any of these if traversal worked.
  test::write_text(dir_ / "secret.txt", "SECRET");
  for (const char* target :
       {"/../secret.txt", "/../etc/passwd", "/%2e%2e/secret.txt", "/%2E%2E/%2e%2e/etc/passwd",
        "/assets/../../secret.txt", "/assets/%2e%2e/%2e%2e/secret.txt", "/..%2fsecret.txt", "/..%5csecret.txt",
        "//etc/passwd", "/%2fetc/passwd", "/%2Fetc%2Fpasswd", "/index.html%00.js"}) {
    SCOPED_TRACE(target);
    const HttpResponse r = call("GET", target);
    EXPECT_TRUE(r.status == 400 || r.status == 404) << r.status;
    EXPECT_EQ(r.body.find("SECRET"), std::string::npos);
    EXPECT_EQ(r.body.find("root:"), std::string::npos);
    EXPECT_EQ(r.content_type, "application/json");
  }
}

TEST_F(RouterTest, NoStaticDirMeans404) {
  Router bare(*meshes_, RouterConfig{});
  expect_error(bare.handle({"GET", "/", "", ""}), 404, "not_found");
  expect_error(bare.handle({"GET", "/index.html", "", ""}), 404, "not_found");
}

TEST(RouterTarget, SplitsAndDecodes) {
  const auto [path, q] = split_target("/a%20b/c?x=1&y=%41+b&flag&=v&z=a%3Db");
  EXPECT_EQ(path, "/a b/c");
  EXPECT_EQ(q.at("x"), "1");
  EXPECT_EQ(q.at("y"), "A b");
  EXPECT_EQ(q.at("flag"), "");
  EXPECT_EQ(q.at("z"), "a=b");
  EXPECT_EQ(split_target("/p").second.size(), 0u);
  EXPECT_EQ(split_target("/p+q").first, "/p+q");  // '+' is a space only in the query
  EXPECT_EQ(split_target("/bad%zz%4").first, "/bad%zz%4");
}

// Every route the router serves is in its OpenAPI document.
TEST_F(RouterTest, OpenApiDocumentsEveryRoute) {
  const json doc = router_->openapi();
  EXPECT_EQ(doc["openapi"].get<std::string>().substr(0, 2), "3.");
  EXPECT_TRUE(doc["info"].contains("title"));
  EXPECT_EQ(doc["info"]["version"], "0.1.0");
  ASSERT_TRUE(doc["paths"].is_object());
  ASSERT_GE(router_->routes().size(), 7u);
  for (const auto& r : router_->routes()) {
    std::string method = r.method;
    for (char& c : method) c = char(std::tolower(static_cast<unsigned char>(c)));
    SCOPED_TRACE(r.method + " " + r.pattern);
    ASSERT_TRUE(doc["paths"].contains(r.pattern));
    ASSERT_TRUE(doc["paths"][r.pattern].contains(method));
    const json& op = doc["paths"][r.pattern][method];
    EXPECT_TRUE(op.contains("summary"));
    EXPECT_FALSE(op["responses"].empty());
    for (std::size_t p = r.pattern.find('{'); p != std::string::npos; p = r.pattern.find('{', p + 1)) {
      const std::string name = r.pattern.substr(p + 1, r.pattern.find('}', p) - p - 1);
      bool documented = false;
      for (const auto& param : op.value("parameters", json::array()))
        documented |= param["name"] == name && param["in"] == "path";
      EXPECT_TRUE(documented) << "path parameter " << name;
    }
    for (const auto& [name, help] : r.query) {
      bool documented = false;
      for (const auto& param : op.value("parameters", json::array()))
        documented |= param["name"] == name && param["in"] == "query";
      EXPECT_TRUE(documented) << "query parameter " << name;
    }
  }
  EXPECT_TRUE(doc["paths"].contains("/api/v1/ws"));
  const HttpResponse served = call("GET", "/api/v1/openapi.json");
  ASSERT_EQ(served.status, 200);
  EXPECT_EQ(json::parse(served.body), doc);
}

// The route table itself: each route once, a method HTTP knows, a path under
// the API (or /metrics) whose parameters are named, and each one in the
// OpenAPI document and in protocol/API.md, where users read about it.
TEST_F(RouterTest, EveryRouteInTheTableIsWellFormedAndDocumented) {
  const auto& routes = router_->routes();
  ASSERT_GE(routes.size(), 20u);
  const std::string api_doc = read_bytes(CGVIEW_API_DOC);
  ASSERT_FALSE(api_doc.empty()) << "cannot read " << CGVIEW_API_DOC;
  const json doc = router_->openapi();
  const std::regex pattern_re(R"(^(/metrics|/api/v1(/([a-z_.]+|\{[a-z_]+\}))+)$)");
  std::set<std::string> seen;
  for (const auto& r : routes) {
    const std::string route = r.method + " " + r.pattern;
    SCOPED_TRACE(route);
    EXPECT_TRUE(seen.insert(route).second) << "declared twice";
    EXPECT_TRUE(r.method == "GET" || r.method == "POST" || r.method == "PUT" || r.method == "DELETE");
    EXPECT_TRUE(std::regex_match(r.pattern, pattern_re)) << "not an API path with named parameters";
    EXPECT_FALSE(r.summary.empty());
    EXPECT_TRUE(r.handler);
    std::string lower = r.method;
    for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
    EXPECT_TRUE(doc["paths"].contains(r.pattern) && doc["paths"][r.pattern].contains(lower))
        << "not in the OpenAPI document";
    EXPECT_NE(api_doc.find("`" + route), std::string::npos)
        << "protocol/API.md does not name it as `" << route << "...`";
  }
}

}  // namespace
}  // namespace cgview::server
