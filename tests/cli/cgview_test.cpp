// The `cgview` command line, run as a real program: help, reports (text and
// JSON), conversion, and one-line error messages with a non-zero status.
#include <gtest/gtest.h>
#include <zip.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <cstring>
#include <string>
#include <vector>

#include "render/image.h"
#include "gltf_quad.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string quote(const std::string& s) { return "'" + s + "'"; }
std::string cgview_cmd(const std::string& args) { return quote(test::bin("cgview")) + " " + args; }

struct Result {
  int status;
  std::string out;  // stdout and stderr together
};
Result cgview(const std::string& args) {
  Result r;
  r.status = test::run(cgview_cmd(args), &r.out);
  return r;
}
// Runs with stderr thrown away: what comes back is stdout alone.
Result cgview_stdout(const std::string& args) {
  Result r;
  r.status = test::run("{ " + cgview_cmd(args) + " 2>/dev/null; }", &r.out);
  return r;
}
// Runs with stdout thrown away: what comes back is stderr alone.
Result cgview_stderr(const std::string& args) {
  Result r;
  r.status = test::run("{ " + cgview_cmd(args) + " 2>&1 >/dev/null; }", &r.out);
  return r;
}

std::vector<std::string> lines(const std::string& s) {
  std::vector<std::string> out;
  std::istringstream in(s);
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

// A failure: non-zero status and exactly one line on stderr, "cgview: ...".
void expect_one_line_error(const std::string& args, const std::string& mention = "") {
  SCOPED_TRACE("cgview " + args);
  const Result r = cgview_stderr(args);
  EXPECT_NE(r.status, 0);
  const auto l = lines(r.out);
  ASSERT_EQ(l.size(), 1u) << "stderr was:\n" << r.out;
  EXPECT_EQ(l[0].rfind("cgview:", 0), 0u) << l[0];
  EXPECT_FALSE(r.out.empty() || r.out.back() != '\n') << "no newline at the end";
  if (!mention.empty()) {
    EXPECT_NE(l[0].find(mention), std::string::npos) << l[0];
  }
  // And nothing on stdout.
  const Result all = cgview_stdout(args);
  EXPECT_EQ(all.out, "");
}

json info_json(const std::string& mesh) {
  const Result r = cgview_stdout("info " + quote(mesh) + " --json");
  EXPECT_EQ(r.status, 0) << r.out;
  try {
    return json::parse(r.out);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not JSON (" << e.what() << "):\n" << r.out;
    return json::object();
  }
}

void expect_elephant(const json& j) {
  for (const char* key :
       {"vertices", "faces", "edges", "bbox", "components", "boundary_loops", "genus", "manifold", "degenerate_faces"})
    EXPECT_TRUE(j.contains(key)) << "missing key " << key;
  EXPECT_EQ(j.value("vertices", 0), 2775);
  EXPECT_EQ(j.value("faces", 0), 5558);
  EXPECT_EQ(j.value("edges", 0), 8337);
  EXPECT_EQ(j.value("components", 0), 1);
  EXPECT_EQ(j.value("boundary_loops", -1), 0);
  ASSERT_TRUE(j.contains("genus") && j["genus"].is_number_integer());
  EXPECT_EQ(j["genus"].get<int>(), 3);
  EXPECT_EQ(j.value("manifold", false), true);
  EXPECT_EQ(j.value("degenerate_faces", -1), 0);
  ASSERT_TRUE(j.contains("bbox") && j["bbox"].is_object());
  const json& b = j["bbox"];
  ASSERT_TRUE(b.contains("min") && b.contains("max"));
  ASSERT_EQ(b["min"].size(), 3u);
  ASSERT_EQ(b["max"].size(), 3u);
  for (int k = 0; k < 3; ++k) EXPECT_LT(b["min"][k].get<double>(), b["max"][k].get<double>());
}

TEST(CliTest, Help) {
  for (const char* flag : {"--help", "-h", "help"}) {
    const Result r = cgview(flag);
    EXPECT_EQ(r.status, 0) << flag;
    EXPECT_NE(r.out.find("usage: cgview"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("info"), std::string::npos);
    EXPECT_NE(r.out.find("convert"), std::string::npos);
    EXPECT_NE(r.out.find("samples"), std::string::npos);
  }
}

TEST(CliTest, CommandHelp) {
  Result r = cgview("info --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("usage: cgview info"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--json"), std::string::npos);

  r = cgview("convert --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("usage: cgview convert"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reads:"), std::string::npos);
  EXPECT_NE(r.out.find("ply"), std::string::npos);

  r = cgview("samples -h");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("usage: cgview samples"), std::string::npos) << r.out;
}

TEST(CliTest, Version) {
  const Result r = cgview("--version");
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("cgview ", 0), 0u) << r.out;
}

TEST(CliTest, InfoJsonOfElephantFile) {
  const json j = info_json(test::sample("elephant.off").string());
  expect_elephant(j);
  EXPECT_EQ(j.value("format", ""), "off");
  EXPECT_EQ(j.value("closed", false), true);
  EXPECT_EQ(j.value("oriented", false), true);
  EXPECT_EQ(j.value("euler_characteristic", 0), -4);
}

TEST(CliTest, InfoBySampleName) {
  const json j = info_json("elephant");
  expect_elephant(j);
  EXPECT_EQ(fs::path(j.value("file", "")).filename(), "elephant.off");
  expect_elephant(info_json("elephant.off"));
}

TEST(CliTest, InfoText) {
  const Result r = cgview("info elephant");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("vertices          2775\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("faces             5558\n"), std::string::npos);
  EXPECT_NE(r.out.find("edges             8337\n"), std::string::npos);
  EXPECT_NE(r.out.find("genus             3\n"), std::string::npos);
  EXPECT_NE(r.out.find("manifold          yes\n"), std::string::npos);
  EXPECT_NE(r.out.find("closed            yes\n"), std::string::npos);
}

// A file of points: info says it is a cloud, and an algorithm that takes
// points (estimate_normals) runs on it and writes the cloud with normals.
TEST(CliTest, APointCloudIsSaidToBeOneAndRunsAnAlgorithmThatTakesPoints) {
  const fs::path dir = test::temp_dir("cli-points");
  std::string xyz;
  for (int i = 0; i < 200; ++i) {
    const double z = 1 - 2 * (i + 0.5) / 200, r = std::sqrt(1 - z * z), phi = 3.883222077450933 * (i + 0.5);
    xyz += std::to_string(r * std::cos(phi)) + " " + std::to_string(r * std::sin(phi)) + " " + std::to_string(z) + "\n";
  }
  test::write_text(dir / "scan.xyz", xyz);
  const Result info = cgview("info " + quote((dir / "scan.xyz").string()));
  ASSERT_EQ(info.status, 0) << info.out;
  EXPECT_NE(info.out.find("faces             0\npoint cloud       yes"), std::string::npos) << info.out;
  const Result run = cgview("run estimate_normals " + quote((dir / "scan.xyz").string()) + " -o " +
                            quote((dir / "with_normals.ply").string()));
  ASSERT_EQ(run.status, 0) << run.out;
  const Mesh back = read_mesh(dir / "with_normals.ply");
  EXPECT_EQ(back.num_vertices(), 200u);
  EXPECT_EQ(back.num_faces(), 0u);
  EXPECT_EQ(back.normals.size(), 200u);
  // An algorithm that needs faces refuses it, saying why.
  const Result faces = cgview("run centroid_distance " + quote((dir / "scan.xyz").string()));
  EXPECT_NE(faces.status, 0);
  EXPECT_NE(faces.out.find("input 'mesh' (scan.xyz) is a point cloud of 200 points and no faces: this algorithm "
                           "needs a mesh with faces"),
            std::string::npos)
      << faces.out;
}

TEST(CliTest, InfoOfNonManifoldMesh) {
  const fs::path dir = test::temp_dir("cli-nonmanifold");
  const fs::path p = dir / "fin.off";
  test::write_text(p, "OFF\n5 3 0\n0 0 0\n1 0 0\n0.5 1 0\n0.5 -1 0\n0.5 0 1\n3 0 1 2\n3 1 0 3\n3 0 1 4\n");
  const json j = info_json(p.string());
  EXPECT_EQ(j.value("faces", 0), 3);
  EXPECT_EQ(j.value("manifold", true), false);
  EXPECT_EQ(j.value("non_manifold_edges", 0), 1);
  EXPECT_TRUE(j.contains("genus") && j["genus"].is_null());
  const Result r = cgview("info " + quote(p.string()));
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("genus             n/a"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("manifold          no (1 non-manifold edges"), std::string::npos) << r.out;
}

TEST(CliTest, WarningsGoToStderrOnly) {
  // The double torus has polygons that are split: a warning, on stderr; the
  // JSON on stdout stays clean.
  const json j = info_json("double-torus-example");
  EXPECT_EQ(j.value("genus", -1), 2);
  EXPECT_EQ(j.value("faces", 0), 466);
  ASSERT_TRUE(j.contains("warnings") && j["warnings"].is_array());
  EXPECT_FALSE(j["warnings"].empty());
  const Result err = cgview_stderr("info double-torus-example --json");
  EXPECT_EQ(err.status, 0);
  const auto l = lines(err.out);
  ASSERT_FALSE(l.empty());
  for (const auto& line : l) EXPECT_EQ(line.rfind("cgview: warning: ", 0), 0u) << line;
}

TEST(CliTest, ConvertToPlyKeepsCounts) {
  const fs::path dir = test::temp_dir("cli-convert");
  for (const char* ext : {"ply", "obj", "off"}) {
    SCOPED_TRACE(ext);
    const fs::path out = dir / (std::string("elephant.") + ext);
    const Result r = cgview("convert elephant " + quote(out.string()));
    ASSERT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(r.out, "");  // quiet on success
    ASSERT_TRUE(fs::exists(out));
    EXPECT_GT(fs::file_size(out), 0u);
    const json j = info_json(out.string());
    expect_elephant(j);
    EXPECT_EQ(j.value("format", ""), ext);
  }
}

TEST(CliTest, ConvertAsciiPly) {
  const fs::path dir = test::temp_dir("cli-convert-ascii");
  const fs::path out = dir / "e.ply";
  ASSERT_EQ(
      cgview("convert " + quote(test::sample("elephant.off").string()) + " " + quote(out.string()) + " --ascii").status,
      0);
  std::ifstream f(out);
  std::string first, second;
  std::getline(f, first);
  std::getline(f, second);
  EXPECT_EQ(first, "ply");
  EXPECT_EQ(second.rfind("format ascii", 0), 0u) << second;
  expect_elephant(info_json(out.string()));
}

// A zip written with libzip, as a user's bundle (the server's zip uploads).
void write_zip(const fs::path& p, const std::vector<std::pair<std::string, std::string>>& files) {
  int err = 0;
  zip_t* z = zip_open(p.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr) << "libzip error " << err;
  for (const auto& [name, bytes] : files) {
    zip_source_t* s = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
    EXPECT_GE(zip_file_add(z, name.c_str(), s, ZIP_FL_ENC_UTF_8), 0) << zip_strerror(z);
  }
  ASSERT_EQ(zip_close(z), 0);
}

// A textured quad: 4 vertices, 2 triangles, its MTL beside it.
const std::string kQuadObj =
    "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl wood\n"
    "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
const std::string kQuadMtl = "newmtl wood\nKd 1 1 1\nmap_Kd maps/wood.png\n";
const std::string kTetraOff = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

// cgview with its temporary directory set, to see that a bundle's is removed.
Result cgview_in_tmp(const fs::path& tmp, const std::string& args) {
  Result r;
  r.status = test::run("TMPDIR=" + quote(tmp.string()) + " " + cgview_cmd(args) + " 2>&1", &r.out);
  return r;
}

TEST(CliTest, InfoAndConvertTakeAZipBundle) {
  const fs::path dir = test::temp_dir("cli-zip");
  const fs::path tmp = dir / "tmp";
  fs::create_directories(tmp);
  const fs::path zip = dir / "quad.zip";
  write_zip(zip, {{"quad/quad.obj", kQuadObj},
                  {"quad/quad.mtl", kQuadMtl},
                  {"quad/maps/wood.png", "not really a PNG"},
                  {"readme.txt", "not a mesh"},
                  // What macOS's Finder adds: not a second mesh.
                  {"__MACOSX/quad/._quad.obj", std::string("\0\5\x16\7", 4)},
                  {"quad/._quad.obj", "x"}});

  const json j = info_json(zip.string());
  EXPECT_EQ(j.value("vertices", 0), 4);
  EXPECT_EQ(j.value("faces", 0), 2);
  EXPECT_EQ(j.value("format", ""), "obj");
  EXPECT_EQ(j.value("entry", ""), "quad/quad.obj");
  EXPECT_EQ(j.value("file", ""), zip.string());

  Result r = cgview_in_tmp(tmp, "info " + quote(zip.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("quad.zip: quad/quad.obj (obj)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("vertices          4\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("faces             2\n"), std::string::npos) << r.out;

  const fs::path out = dir / "quad.ply";
  r = cgview_in_tmp(tmp, "convert " + quote(zip.string()) + " " + quote(out.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "");
  const json back = info_json(out.string());
  EXPECT_EQ(back.value("format", ""), "ply");
  EXPECT_EQ(back.value("vertices", 0), 4);
  EXPECT_EQ(back.value("faces", 0), 2);
  EXPECT_TRUE(fs::is_empty(tmp)) << "the unpacked bundle was left behind";

  // An OFF alone in a zip, the extension in capitals.
  const fs::path off_zip = dir / "TETRA.ZIP";
  write_zip(off_zip, {{"tetra.off", kTetraOff}});
  const json t = info_json(off_zip.string());
  EXPECT_EQ(t.value("vertices", 0), 4);
  EXPECT_EQ(t.value("faces", 0), 4);
  EXPECT_EQ(t.value("genus", -1), 0);
  const fs::path off_out = dir / "tetra.obj";
  ASSERT_EQ(cgview("convert " + quote(off_zip.string()) + " " + quote(off_out.string())).status, 0);
  EXPECT_EQ(info_json(off_out.string()).value("faces", 0), 4);
}

TEST(CliTest, GltfWithItsBinBesideItOrZipped) {
  const fs::path dir = test::temp_dir("cli-gltf");
  fs::create_directories(dir / "buffers");
  test::write_text(dir / "quad.gltf", test::gltf_quad("buffers/quad%20data.bin"));
  test::write_text(dir / "buffers" / "quad data.bin", test::gltf_quad_bin());
  const json j = info_json((dir / "quad.gltf").string());
  EXPECT_EQ(j.value("vertices", 0), 4);
  EXPECT_EQ(j.value("faces", 0), 2);
  const fs::path out = dir / "quad.ply";
  ASSERT_EQ(cgview("convert " + quote((dir / "quad.gltf").string()) + " " + quote(out.string())).status, 0);
  EXPECT_EQ(info_json(out.string()).value("faces", 0), 2);

  // Zipped together, the .gltf in a folder of the zip.
  const fs::path zip = dir / "quad.zip";
  write_zip(zip, {{"model/quad.gltf", test::gltf_quad("quad.bin")}, {"model/quad.bin", test::gltf_quad_bin()}});
  const json z = info_json(zip.string());
  EXPECT_EQ(z.value("faces", 0), 2);
  EXPECT_EQ(z.value("format", ""), "gltf");

  // The .bin missing, or named outside the .gltf's directory: refused, saying why.
  test::write_text(dir / "buffers" / "alone.gltf", test::gltf_quad("missing.bin"));
  Result r = cgview("info " + quote((dir / "buffers" / "alone.gltf").string()));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("the file 'missing.bin' it names is missing: upload it together with the .gltf"),
            std::string::npos)
      << r.out;
  test::write_text(dir / "buffers" / "up.gltf", test::gltf_quad("../buffers/quad%20data.bin"));
  r = cgview("info " + quote((dir / "buffers" / "up.gltf").string()));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("is refused: it leaves the .gltf's directory"), std::string::npos) << r.out;
  // A symbolic link out of the directory is no companion.
  fs::create_directories(dir / "inner");
  fs::create_symlink(dir / "buffers" / "quad data.bin", dir / "inner" / "link.bin");
  test::write_text(dir / "inner" / "link.gltf", test::gltf_quad("link.bin"));
  r = cgview("info " + quote((dir / "inner" / "link.gltf").string()));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("'link.bin' it names is missing"), std::string::npos) << r.out;

  // A base-colour texture beside it is read; missing, a warning names it.
  std::string textured = test::gltf_quad("quad.bin");
  auto put = [&](const std::string& what, const std::string& with) {
    const std::size_t at = textured.find(what);
    ASSERT_NE(at, std::string::npos) << what;
    textured.replace(at, what.size(), with);
  };
  put(R"("POSITION":0})", R"("POSITION":0,"TEXCOORD_0":2})");
  put(R"("indices":1})", R"("indices":1,"material":0})");
  put(R"("type":"SCALAR"}])", R"("type":"SCALAR"},{"bufferView":0,"componentType":5126,"count":4,"type":"VEC2"}])");
  put(R"({"asset":{"version":"2.0"},)",
      R"({"asset":{"version":"2.0"},"materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}],)"
      R"("textures":[{"source":0}],"images":[{"uri":"tex.png"}],)");
  const fs::path tex_dir = dir / "textured";
  fs::create_directories(tex_dir);
  test::write_text(tex_dir / "quad.gltf", textured);
  test::write_text(tex_dir / "quad.bin", test::gltf_quad_bin());
  test::write_text(tex_dir / "tex.png", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\1\0\0\0\1\x08\x02\0\0\0", 29));
  EXPECT_EQ(info_json((tex_dir / "quad.gltf").string())["warnings"], json::array());
  fs::remove(tex_dir / "tex.png");
  const json w = info_json((tex_dir / "quad.gltf").string());
  ASSERT_EQ(w["warnings"].size(), 1u) << w;
  EXPECT_NE(w["warnings"][0].get<std::string>().find("the file 'tex.png' it names is missing"), std::string::npos)
      << w["warnings"];
}

TEST(CliTest, ZipBundleErrors) {
  const fs::path dir = test::temp_dir("cli-zip-errors");
  const fs::path tmp = dir / "tmp";
  fs::create_directories(tmp);
  const fs::path none = dir / "none.zip";
  write_zip(none, {{"readme.txt", "no mesh here"}, {"quad.mtl", kQuadMtl}});
  expect_one_line_error("info " + quote(none.string()), "no mesh file");
  expect_one_line_error("convert " + quote(none.string()) + " " + quote((dir / "o.ply").string()), "no mesh file");
  EXPECT_FALSE(fs::exists(dir / "o.ply"));
  EXPECT_EQ(cgview_in_tmp(tmp, "info " + quote(none.string())).status, 1);

  const fs::path two = dir / "two.zip";
  write_zip(two, {{"a.obj", kQuadObj}, {"b.off", kTetraOff}});
  expect_one_line_error("info " + quote(two.string()), "several mesh files");

  const fs::path not_zip = dir / "not.zip";
  test::write_text(not_zip, kTetraOff);
  expect_one_line_error("info " + quote(not_zip.string()), "not a readable zip");

  // A zip-slip name is refused, nothing written outside.
  const fs::path slip = dir / "slip.zip";
  write_zip(slip, {{"../evil.off", kTetraOff}});
  expect_one_line_error("info " + quote(slip.string()), "unsafe path");
  EXPECT_FALSE(fs::exists(dir / "evil.off"));

  // A malformed mesh in a zip is named by the zip and its entry.
  const fs::path bad = dir / "bad.zip";
  write_zip(bad, {{"m/bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"}});
  expect_one_line_error("info " + quote(bad.string()), "bad.zip:m/bad.off");
  EXPECT_EQ(cgview_in_tmp(tmp, "info " + quote(bad.string())).status, 1);
  EXPECT_TRUE(fs::is_empty(tmp)) << "the unpacked bundle was left behind";
}

TEST(CliTest, ErrorMissingFile) {
  expect_one_line_error("info /nonexistent/dir/mesh.off", "/nonexistent/dir/mesh.off");
  expect_one_line_error("info no_such_sample_name_xyz", "no_such_sample_name_xyz");
  expect_one_line_error("convert /nonexistent/in.off " + quote((test::temp_dir("cli-missing") / "o.ply").string()));
}

TEST(CliTest, ErrorUnknownExtension) {
  const fs::path dir = test::temp_dir("cli-ext");
  const fs::path p = dir / "mesh.las";
  test::write_text(p, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  expect_one_line_error("info " + quote(p.string()), "las");
  expect_one_line_error("convert elephant " + quote((dir / "out.abc").string()), "abc");
  EXPECT_FALSE(fs::exists(dir / "out.abc"));
}

TEST(CliTest, ErrorUnknownCommandAndUsage) {
  expect_one_line_error("frobnicate", "frobnicate");
  expect_one_line_error("");
  expect_one_line_error("info");
  expect_one_line_error("info elephant --bogus", "--bogus");
  expect_one_line_error("info elephant elephant");
  expect_one_line_error("convert elephant");
  expect_one_line_error("convert elephant out.ply --bits", "--bits");
  expect_one_line_error("convert elephant out.ply --bits x12", "x12");
  // Usage errors exit with 2, other errors with 1.
  EXPECT_EQ(cgview("frobnicate").status, 2);
  EXPECT_EQ(cgview("info /nonexistent.off").status, 1);
}

TEST(CliTest, ErrorMalformedFile) {
  const fs::path dir = test::temp_dir("cli-malformed");
  const fs::path bad_index = dir / "bad_index.off";
  test::write_text(bad_index, "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  expect_one_line_error("info " + quote(bad_index.string()), "bad_index.off");

  const fs::path garbage = dir / "garbage.off";
  test::write_text(garbage, "this is not\nan OFF file\n");
  expect_one_line_error("info " + quote(garbage.string()), "garbage.off");

  const fs::path truncated = dir / "truncated.off";
  test::write_text(truncated, "OFF\n4 2 0\n0 0 0\n1 0 0\n");
  expect_one_line_error("info " + quote(truncated.string()), "truncated.off");

  const fs::path bad_ply = dir / "bad.ply";
  test::write_text(bad_ply,
                   "ply\nformat binary_little_endian 1.0\nelement vertex 1000000\n"
                   "property float x\nproperty float y\nproperty float z\nend_header\n\x01\x02");
  expect_one_line_error("info " + quote(bad_ply.string()), "bad.ply");

  expect_one_line_error("convert " + quote(garbage.string()) + " " + quote((dir / "o.ply").string()));
  EXPECT_FALSE(fs::exists(dir / "o.ply"));
}

TEST(CliTest, Samples) {
  Result r = cgview("samples");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("elephant.off"), std::string::npos);
  r = cgview_stdout("samples --json");
  ASSERT_EQ(r.status, 0);
  const json j = json::parse(r.out);
  ASSERT_TRUE(j.is_array());
  bool found = false;
  for (const auto& e : j)
    if (e.value("name", "") == "elephant") {
      found = true;
      EXPECT_TRUE(fs::exists(e.value("path", "")));
    }
  EXPECT_TRUE(found);
}

// ---------------------------------------------------------------- algorithms

TEST(CliTest, ListShowsCentroidDistance) {
  const Result r = cgview_stdout("list");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("centroid_distance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--exponent number"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--normalize boolean"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max 4"), std::string::npos) << r.out;
}

TEST(CliTest, ListJsonHasTheSchemas) {
  const Result r = cgview_stdout("list --json");
  ASSERT_EQ(r.status, 0) << r.out;
  json j;
  ASSERT_NO_THROW(j = json::parse(r.out)) << r.out;
  ASSERT_TRUE(j.is_array());
  const json* cd = nullptr;
  for (const auto& a : j)
    if (a.value("name", "") == "centroid_distance") cd = &a;
  ASSERT_NE(cd, nullptr) << r.out;
  const json& e = (*cd)["params"]["properties"]["exponent"];
  EXPECT_EQ(e["maximum"], 4);
  EXPECT_EQ(e["minimum"], 0.1);
  EXPECT_EQ(e["default"], 1.0);
  EXPECT_EQ(e["type"], "number");
  EXPECT_EQ((*cd)["params"]["properties"]["normalize"]["type"], "boolean");
  EXPECT_EQ((*cd)["outputs"][0]["kind"], "scalar_field");
  expect_one_line_error("list --bogus", "--bogus");
}

TEST(CliTest, RunCentroidDistanceWritesOneValuePerVertex) {
  const fs::path dir = test::temp_dir("cli-run");
  const fs::path out = dir / "d.txt";
  const Result r = cgview_stdout("run centroid_distance " + quote(test::sample("elephant.off").string()) + " -o " +
                                 quote(out.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_EQ(r.out, "distance: " + out.string() + "\n");
  std::ifstream in(out);
  std::vector<double> values;
  for (std::string l; std::getline(in, l);) values.push_back(std::stod(l));
  ASSERT_EQ(values.size(), 2775u);
  for (double v : values) EXPECT_GE(v, 0.0);

  // --normalize: the largest becomes 1; --exponent 2 squares each distance.
  const fs::path norm = dir / "n.csv", squared = dir / "s.txt";
  ASSERT_EQ(cgview("run centroid_distance elephant --normalize true -o " + quote(norm.string())).status, 0);
  std::ifstream nin(norm);
  std::string header, row;
  std::getline(nin, header);
  EXPECT_EQ(header, "vertex,centroid_distance");
  double largest = 0;
  std::size_t rows = 0;
  while (std::getline(nin, row)) {
    largest = std::max(largest, std::stod(row.substr(row.find(',') + 1)));
    ++rows;
  }
  EXPECT_EQ(rows, 2775u);
  EXPECT_NEAR(largest, 1.0, 1e-6);
  ASSERT_EQ(cgview("run centroid_distance elephant --exponent 2 -o " + quote(squared.string())).status, 0);
  std::ifstream sin(squared);
  std::string l;
  for (std::size_t i = 0; i < values.size() && std::getline(sin, l); ++i)
    EXPECT_NEAR(std::stod(l), values[i] * values[i], 1e-5 * (1 + values[i] * values[i]));
}

TEST(CliTest, RunSavesPlyWithTheField) {
  const fs::path out = test::temp_dir("cli-run-ply") / "d.ply";
  ASSERT_EQ(cgview("run centroid_distance elephant -o " + quote(out.string())).status, 0);
  std::ifstream in(out, std::ios::binary);
  std::string header;
  for (std::string l; std::getline(in, l) && l != "end_header";) header += l + "\n";
  EXPECT_NE(header.find("property float centroid_distance"), std::string::npos) << header;
  expect_elephant(info_json(out.string()));
}

TEST(CliTest, RunTakesAGridFileAndASecondMesh) {
  const fs::path dir = test::temp_dir("cli-run-inputs");
  // A voxel grid saved by voxelize is grid_surface's input.
  const fs::path grid = dir / "e.nrrd", surface = dir / "s.ply";
  ASSERT_EQ(cgview("run voxelize elephant --resolution 20 -o " + quote(grid.string())).status, 0);
  const Result r = cgview("run grid_surface " + quote(grid.string()) + " -o " + quote(surface.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream a(dir / "e-metrics.json"), b(dir / "s-metrics.json");
  const auto va = nlohmann::json::parse(a), vb = nlohmann::json::parse(b);
  EXPECT_EQ(va["occupied_voxels"], vb["voxels"]) << va.dump() << vb.dump();
  // hausdorff takes its reference as --reference FILE, and names it when it is missing.
  const Result h = cgview("run hausdorff elephant --reference elephant -o " + quote((dir / "h.ply").string()));
  ASSERT_EQ(h.status, 0) << h.out;
  std::ifstream m(dir / "h-metrics.json");
  EXPECT_LE(nlohmann::json::parse(m)["hausdorff"].get<double>(), 1e-3);
  const Result missing = cgview_stderr("run hausdorff elephant");
  EXPECT_NE(missing.status, 0);
  EXPECT_NE(missing.out.find("--reference FILE"), std::string::npos) << missing.out;
}

TEST(CliTest, RunBadParameterIsOneLineNamingIt) {
  expect_one_line_error("run centroid_distance elephant --exponent 9", "parameter 'exponent': 9 is over the maximum 4");
  EXPECT_EQ(cgview("run centroid_distance elephant --exponent 9").status, 1);
  expect_one_line_error("run centroid_distance elephant --exponent two", "parameter 'exponent'");
  expect_one_line_error("run centroid_distance elephant --normalize maybe", "parameter 'normalize'");
  expect_one_line_error("run centroid_distance elephant --bogus 1", "--bogus");
  expect_one_line_error("run centroid_distance elephant --exponent", "--exponent");
  expect_one_line_error("run centroid_distance", "which mesh");
  expect_one_line_error(
      "run centroid_distance elephant -o " + quote((test::temp_dir("cli-run-ext") / "d.vtk").string()), "vtk");
}

TEST(CliTest, RunTakesASelectionAsListOrFile) {
  const fs::path dir = test::temp_dir("cli-run-selection");
  const fs::path out = dir / "part.off", ids = dir / "ids.txt";
  Result r = cgview("run extract_faces elephant --faces 10,3,7 -o " + quote(out.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream m(dir / "part-metrics.json");
  EXPECT_EQ(nlohmann::json::parse(m)["faces"], 3);
  {
    std::ofstream f(ids);
    f << "1 2\n3,4\n5\n";
  }
  r = cgview("run extract_faces elephant --faces @" + quote(ids.string()) + " --invert true -o " + quote(out.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  std::ifstream m2(dir / "part-metrics.json");
  EXPECT_EQ(nlohmann::json::parse(m2)["faces"], 5558 - 5);
  expect_one_line_error("run extract_faces elephant --faces 1,99999",
                        "face id 99999 is out of range (the mesh has 5558 faces)");
  expect_one_line_error("run extract_faces elephant --faces 1,x", "parameter 'faces'");
}

TEST(CliTest, RunUnknownAlgorithmHints) {
  expect_one_line_error("run no_such_algo elephant", "no_such_algo");
  const Result r = cgview_stderr("run no_such_algo elephant");
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.out.find("cgview list"), std::string::npos) << r.out;
}

TEST(CliTest, RunHelpListsTheParameters) {
  Result r = cgview_stdout("run centroid_distance --help");
  ASSERT_EQ(r.status, 0) << r.out;
  EXPECT_NE(r.out.find("usage: cgview run centroid_distance"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--exponent"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--normalize"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Exponent (default 1, min 0.1, max 4)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("distance (scalar_field)"), std::string::npos) << r.out;
  r = cgview_stdout("run --help");
  EXPECT_EQ(r.status, 0);
  EXPECT_NE(r.out.find("usage: cgview run ALGO"), std::string::npos) << r.out;
}

TEST(CliTest, RunReportsProgressOnStderrWhenNotATerminal) {
  const fs::path out = test::temp_dir("cli-run-progress") / "d.txt";
  const Result r = cgview_stderr("run centroid_distance elephant -o " + quote(out.string()));
  ASSERT_EQ(r.status, 0) << r.out;
  const auto l = lines(r.out);
  ASSERT_FALSE(l.empty());
  for (const auto& line : l) EXPECT_EQ(line.rfind("progress ", 0), 0u) << line;  // plain lines, no \r bar
  EXPECT_EQ(r.out.find('\r'), std::string::npos);
  EXPECT_NE(l.back().find("100%"), std::string::npos) << r.out;
}

render::Image read_png_file(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  return render::decode_png(bytes);
}

TEST(CliTest, RenderWritesAPng) {
  const fs::path dir = test::temp_dir("cli_render");
  const fs::path out = dir / "elephant.png";
  const Result r = cgview("render elephant -o " + quote(out.string()) + " --mode toon --size 120x90");
  ASSERT_EQ(r.status, 0) << r.out;
  const render::Image im = read_png_file(out);
  EXPECT_EQ(im.width, 120);
  EXPECT_EQ(im.height, 90);
  // --views N: a contact sheet of N cells (about square: 3 x 2 for 5).
  const fs::path sheet = dir / "sheet.png";
  const Result s = cgview("render elephant -o " + quote(sheet.string()) + " --views 5 --size 40x30");
  ASSERT_EQ(s.status, 0) << s.out;
  const render::Image sh = read_png_file(sheet);
  EXPECT_EQ(sh.width, 3 * 40);
  EXPECT_EQ(sh.height, 2 * 30);
  // A silhouette is black and white only.
  const fs::path mask = dir / "mask.png";
  ASSERT_EQ(cgview("render elephant --silhouette --ortho -o " + quote(mask.string()) + " --size 32x32").status, 0);
  for (std::uint8_t v : read_png_file(mask).rgba) EXPECT_TRUE(v == 0 || v == 255);
  // Depth and face ids as raw arrays, one value per pixel.
  const fs::path depth = dir / "depth.f32", ids = dir / "ids.u32";
  ASSERT_EQ(cgview("render elephant -o " + quote((dir / "d.png").string()) + " --size 20x10 --depth " +
                   quote(depth.string()) + " --face-ids " + quote(ids.string()))
                .status,
            0);
  EXPECT_EQ(fs::file_size(depth), 20u * 10u * 4u);
  EXPECT_EQ(fs::file_size(ids), 20u * 10u * 4u);
  fs::remove_all(dir);
}

TEST(CliTest, RenderBadInput) {
  expect_one_line_error("render elephant -o x.png --size 0x10", "width");
  expect_one_line_error("render elephant -o x.png --size 10x9000", "height");
  expect_one_line_error("render elephant -o x.png --size big", "--size");
  expect_one_line_error("render elephant -o x.png --mode phong", "mode");
  expect_one_line_error("render elephant -o x.png --views 0", "--views");
  expect_one_line_error("render elephant", "-o");
  expect_one_line_error("render elephant -o x.png --gl-platform x11", "--gl-platform");
}

}  // namespace
}  // namespace cgview
