// No upload takes the server down: the real cgview-server reads each upload
// in a child process (cgview-read) with the jobs' memory
// limit and its own time limit.  Hostile files of each class (counts that
// lie, deep nesting, numbers that overflow, every format's decoder) answer
// 4xx with what was wrong, never 500; a reader that crashes or hangs costs
// its upload a 400 or 413; a reader sees only its own directory (the
// jobs' sandbox); and meanwhile the server answers others.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <future>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "io/mesh_io.h"
#include "server_harness.h"
#include "test_support.h"

namespace cgview::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

// 33 bytes of Draco whose header claims 1.4 billion faces: Draco's decoder
// sizes its corner table (tens of GB) from the claim.
std::string draco_claiming_billions() { return draco_claiming(1400000000); }

std::string le32(std::uint32_t v) { return {char(v), char(v >> 8), char(v >> 16), char(v >> 24)}; }

// A .glb around a JSON chunk and a BIN chunk.
std::string glb(std::string json_text, std::string bin) {
  while (json_text.size() % 4) json_text += ' ';
  while (bin.size() % 4) bin += '\0';
  std::string body = le32(std::uint32_t(json_text.size())) + "JSON" + json_text;
  if (!bin.empty()) body += le32(std::uint32_t(bin.size())) + "BIN" + '\0' + bin;
  return "glTF" + le32(2) + le32(std::uint32_t(12 + body.size())) + body;
}

// The same Draco claim as a glTF primitive's KHR_draco_mesh_compression.
std::string glb_with_draco_claiming_billions() {
  const std::string d = draco_claiming_billions();
  const json doc = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_draco_mesh_compression"}},
      {"buffers", {{{"byteLength", d.size()}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", d.size()}}}},
      {"accessors", {{{"componentType", 5126}, {"count", 3}, {"type", "VEC3"}}}},
      {"meshes",
       {{{"primitives",
          {{{"attributes", {{"POSITION", 0}}},
            {"extensions",
             {{"KHR_draco_mesh_compression", {{"bufferView", 0}, {"attributes", {{"POSITION", 0}}}}}}}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}}};
  return glb(doc.dump(), d);
}

// A glTF whose "indices" is an array nested 200,000 deep: dumping it in an
// error message recursed once a level and overflowed the stack.
std::string gltf_nested(std::size_t depth) {
  return R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":)" +
         std::string(depth, '[') + std::string(depth, ']') + "}]}]}";
}

class UploadIsolation : public ServerFixture {
 protected:
  UploadIsolation() : ServerFixture("upload-isolation-") {}

  HttpResult upload(const std::string& name, const std::string& bytes) {
    return http_call(port(), Method::post, "/api/v1/meshes?name=" + name, bytes, 60s);
  }

  // A 4xx with a JSON error whose detail holds `says`.
  void expect_refused(const HttpResult& r, unsigned status, const std::string& says) {
    ASSERT_FALSE(r.ec) << r.ec.message();
    EXPECT_EQ(r.status, status) << r.body;
    const json j = r.body_json();
    EXPECT_TRUE(j.is_object() && j.contains("error")) << r.body;
    EXPECT_NE(j.value("detail", "").find(says), std::string::npos) << "detail should say '" << says << "': " << r.body;
  }

  // A shell script standing in for the upload reader (cgview-read).
  fs::path script(const std::string& name, const std::string& body) {
    fs::create_directories(dir_);
    const fs::path p = dir_ / name;
    write_text(p, "#!/bin/sh\n" + body + "\n");
    ::chmod(p.c_str(), 0755);
    return p;
  }

  std::size_t meshes() {
    const json j = http_get(port(), "/api/v1/meshes").body_json();
    return j.contains("meshes") ? j["meshes"].size() : std::size_t(-1);
  }
};

TEST_F(UploadIsolation, HostileFilesOfEveryFormatAre4xxAndTheServerGoesOn) {
  ASSERT_TRUE(server_.start(data_, {}, dir_));
  struct Case {
    std::string name, bytes;
    unsigned status;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"lie.drc", draco_claiming_billions(), 400, "claims 1400000000 faces"},
      {"lie.glb", glb_with_draco_claiming_billions(), 400, "claims 1400000000 faces"},
      {"deep.gltf", gltf_nested(200000), 400, "nests arrays and objects 200005 deep"},
      {"deep.glb", glb(gltf_nested(200000), ""), 400, "nests arrays and objects 200005 deep"},
      {"lie.off", "OFF\n2000000000 4000000000 0\n0 0 0\n", 400,
       "lie.off: line 2: the header claims 2000000000 vertices, but only 7 bytes follow"},
      {"lie.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\n"
       "property float y\nproperty float z\nelement face 4000000000\nproperty list uchar int vertex_indices\n"
       "end_header\n" +
           std::string(64, '\0'),
       400, "lie.ply: line 9: the header claims 4000000000 vertex elements"},
      {"lie.stl", std::string(80, ' ') + le32(4000000000u) + std::string(50, '\0'), 400,
       "lie.stl: byte 80: a binary STL header claims 4000000000 triangles"},
      {"overflow.obj", "v 1e999 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 99999999999999999999\n", 400,
       "overflow.obj: line 1: vertex 1 has a non-finite coordinate"},
      {"overflow.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 18446744073709551617\n", 400,
       "overflow.off: line 6: expected a vertex index, found '18446744073709551617'"},
      {"notazip.zip", "PK\x03\x04 this is not a zip", 400, "not a readable zip"},
      // A message quoting bytes that are not UTF-8 (found by tests/soak): still
      // a 400 that says where, the bytes replaced by U+FFFD.
      {"latin1.off", "caf\xe9\n3 1 0\n", 400,
       "latin1.off: line 1: not an OFF file: it starts with caf\xef\xbf\xbd, not OFF"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const auto t0 = Clock::now();
    expect_refused(upload(c.name, c.bytes), c.status, c.says);
    EXPECT_LT(Clock::now() - t0, 20s);
    expect_healthy();
  }
  EXPECT_EQ(meshes(), 0u);
  // A good file after all that is read and stored.
  const HttpResult ok = upload("elephant.off", read_bytes(sample("elephant.off")));
  EXPECT_EQ(ok.status, 201u) << ok.body;
  EXPECT_EQ(ok.body_json()["report"].value("faces", 0), 5558);
  EXPECT_EQ(meshes(), 1u);
  // Nothing is left of the readers' files.
  std::size_t left = 0;
  for (const auto& e : fs::directory_iterator(data_ / "tmp"))
    left += e.path().filename().string().starts_with("upload-");
  EXPECT_EQ(left, 0u);
}

TEST_F(UploadIsolation, AReaderThatCrashesFailsItsUploadAlone) {
  // The stand-in reader dies as a parser's crash would.
  const fs::path crash = script("crash-reader", "kill -SEGV $$");
  ASSERT_TRUE(server_.start(data_, {"--reader", crash.string()}, dir_));
  expect_refused(upload("a.off", read_bytes(sample("elephant.off"))), 400, "SIGSEGV");
  expect_healthy();
  EXPECT_EQ(meshes(), 0u);
}

TEST_F(UploadIsolation, AReaderSeesOnlyItsOwnDirectoryNeitherTheDataNorTheNetwork) {
  // The stand-in reader does what a parser taken over by its file could:
  // it looks for the server's database, writes beside it, and looks for a
  // network (a namespace of its own has only loopback); then it says in its
  // refusal what it found.
  std::string body = R"sh(found=''
[ -e 'DATA/cgview.db' ] && found="$found database"
touch 'DATA/escaped' 2>/dev/null && found="$found wrote"
[ "$(grep -c : /proc/net/dev)" -gt 1 ] && found="$found network"
ls /run/cgview/job/upload >/dev/null || found="$found no-upload"
printf '{"error":"invalid_mesh","detail":"found:%s."}' "$found" > "$2/error.json"
exit 2)sh";
  for (std::size_t at; (at = body.find("DATA")) != std::string::npos;) body.replace(at, 4, data_.string());
  const fs::path nosy = script("nosy-reader", body);
  ASSERT_TRUE(server_.start(data_, {"--reader", nosy.string()}, dir_));
  ASSERT_TRUE(fs::exists(data_ / "cgview.db"));
  expect_refused(upload("a.off", read_bytes(sample("elephant.off"))), 400, "found:.");
  EXPECT_FALSE(fs::exists(data_ / "escaped"));
  expect_healthy();
}

TEST_F(UploadIsolation, AReaderOverItsTimeLimitIs413WhileOthersAreServed) {
  const fs::path hang = script("hang-reader", "exec sleep 600");
  ASSERT_TRUE(server_.start(data_, {"--reader", hang.string(), "--upload-timeout-s", "2"}, dir_));
  const auto t0 = Clock::now();
  auto slow = std::async(std::launch::async, [&] { return upload("a.off", read_bytes(sample("elephant.off"))); });
  // Others are served while the upload is read.
  std::this_thread::sleep_for(300ms);
  for (int i = 0; i < 5; ++i) {
    const auto t = Clock::now();
    expect_healthy();
    EXPECT_EQ(http_get(port(), "/api/v1/meshes").status, 200u);
    EXPECT_LT(Clock::now() - t, 1s);
  }
  const HttpResult r = slow.get();
  expect_refused(r, 413, "longer than the server allows for one upload (2 s)");
  EXPECT_GE(Clock::now() - t0, 2s);
  EXPECT_LT(Clock::now() - t0, 10s);
  expect_healthy();
}

TEST_F(UploadIsolation, AFileThatNeedsMoreMemoryThanTheLimitIs413) {
  // The reader takes about 260 MB for this 38 MB PLY of 2 million faces,
  // past a 128 MB limit; the elephant reads within 16 MB.
  ASSERT_TRUE(server_.start(data_, {"--job-memory-mb", "128"}, dir_));
  const std::string big = write_mesh_bytes(grid(1000), MeshFormat::ply);
  expect_refused(upload("grid.ply", big), 413,
                 "grid.ply: reading it needs more memory than the server allows for one upload (128 MB)");
  expect_healthy();
  EXPECT_EQ(meshes(), 0u);
  const HttpResult ok = upload("elephant.off", read_bytes(sample("elephant.off")));
  EXPECT_EQ(ok.status, 201u) << ok.body;
  EXPECT_EQ(meshes(), 1u);
}

}  // namespace
}  // namespace cgview::test
