// Zip uploads of textured meshes through the router (no sockets): an OBJ
// with its MTL and image, a PLY with `comment TextureFile`, a missing image
// (a warning, not an error), the texture route, and the zips refused:
// zip-slip names, one that unpacks past the upload limit, not a zip, none
// or several meshes.  The zips are made with libzip here.
#include <gtest/gtest.h>
#include <zip.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <map>
#include <fstream>
#include <set>
#include <sstream>

#include "draco_faces.h"
#include "io/materials.h"
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

const std::string kQuad =
    "mtllib quad.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "usemtl skin\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
// Written on Windows: a backslash path in other case than the file's.
const std::string kMtl = "newmtl skin\nKd 0.5 0.25 1\nmap_Kd .\\Maps\\WOOD.JPG\n";

// A zip as macOS's Archive Utility writes one: each entry followed by a data
// descriptor, its local header giving the compressed size but no CRC or size
// (libzip's ZIP_CHECKCONS calls that inconsistent before 1.10.1; unzip -t
// accepts it).  Stored entries, written byte by byte.
std::string archive_utility_zip(const std::vector<std::pair<std::string, std::string>>& files) {
  auto u16 = [](std::string& s, std::size_t v) {
    s += char(v & 0xff);
    s += char((v >> 8) & 0xff);
  };
  auto u32 = [&](std::string& s, std::size_t v) {
    u16(s, v & 0xffff);
    u16(s, (v >> 16) & 0xffff);
  };
  auto crc32 = [](const std::string& b) {
    std::uint32_t c = 0xffffffff;
    for (const unsigned char x : b) {
      c ^= x;
      for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1)));
    }
    return ~c;
  };
  std::string out, central;
  for (const auto& [name, bytes] : files) {
    const std::size_t offset = out.size(), crc = crc32(bytes), size = bytes.size();
    // Local header: version 2.0, flag 8 (data descriptor), stored, a date; CRC 0, the compressed size, size 0.
    out += "PK\3\4";
    for (const std::size_t v : {20, 8, 0, 0, 0x21}) u16(out, v);
    u32(out, 0);
    u32(out, size);
    u32(out, 0);
    u16(out, name.size());
    u16(out, 0);
    out += name + bytes;
    out += "PK\7\x08";
    for (const std::size_t v : {crc, size, size}) u32(out, v);
    central += "PK\1\2";
    for (const std::size_t v : {0x314, 20, 8, 0, 0, 0x21}) u16(central, v);
    for (const std::size_t v : {crc, size, size}) u32(central, v);
    for (const std::size_t v : {name.size(), std::size_t(0), std::size_t(0), std::size_t(0), std::size_t(0)})
      u16(central, v);
    u32(central, 0);
    u32(central, offset);
    central += name;
  }
  const std::size_t central_at = out.size();
  out += central + "PK\5\6";
  for (const std::size_t v : {std::size_t(0), std::size_t(0), files.size(), files.size()}) u16(out, v);
  u32(out, central.size());
  u32(out, central_at);
  u16(out, 0);
  return out;
}

class TextureUploadTest : public test::RouterFixture {
 protected:
  void SetUp() override {
    make_dir("texture-");
    open(dir_ / "data", std::nullopt, RouterConfig{dir_ / "static", "0.1.0"});
    jpeg_ = read_bytes("/usr/share/assimp/models/OBJ/drkwood2.jpg");
    ASSERT_FALSE(jpeg_.empty()) << "install Debian's assimp-testmodels";
  }
  // A zip of (name, bytes) entries, written by libzip.
  std::string make_zip(const std::vector<std::pair<std::string, std::string>>& files, bool compress = true) {
    const fs::path p = dir_ / "made.zip";
    fs::remove(p);
    int err = 0;
    zip_t* z = zip_open(p.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    EXPECT_NE(z, nullptr) << "libzip error " << err;
    if (!z) return {};
    for (const auto& [name, bytes] : files) {
      zip_source_t* s = zip_source_buffer(z, bytes.data(), bytes.size(), 0);
      const zip_int64_t i = zip_file_add(z, name.c_str(), s, ZIP_FL_ENC_UTF_8);
      EXPECT_GE(i, 0) << zip_strerror(z);
      if (!compress) zip_set_file_compression(z, zip_uint64_t(i), ZIP_CM_STORE, 0);
    }
    EXPECT_EQ(zip_close(z), 0);
    return read_bytes(p);
  }

  HttpResponse call(const std::string& method, const std::string& target, std::string body = "") {
    return router_->handle({method, target, std::move(body), ""});
  }
  json upload(const std::string& name, const std::string& bytes, int status = 201) {
    const HttpResponse r = call("POST", "/api/v1/meshes?name=" + name, bytes);
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_EQ(r.content_type, "application/json");
    return json::parse(r.body);
  }
  // The error code of a refused upload, with its detail checked to hold `says`.
  void refused(const std::string& name, const std::string& bytes, int status, const std::string& says) {
    const json j = upload(name, bytes, status);
    EXPECT_NE(j.value("detail", "").find(says), std::string::npos) << j.dump();
    EXPECT_EQ(store_->list_meshes().size(), 0u) << "nothing stored";
  }

  std::string jpeg_;
};

TEST_F(TextureUploadTest, ObjMtlAndImageKeepTheirTexture) {
  const json mesh = upload("quad.zip", make_zip({{"quad/quad.obj", kQuad},
                                                 {"quad/quad.mtl", kMtl},
                                                 {"quad/maps/wood.jpg", jpeg_},
                                                 {"readme.txt", "not a mesh"},
                                                 // What macOS's Finder adds: not a second mesh.
                                                 {"__MACOSX/quad/._quad.obj", "\0\5\x16\7"},
                                                 {"quad/._quad.obj", "x"}}));
  EXPECT_EQ(mesh["name"], "quad.obj");
  EXPECT_EQ(mesh["format"], "obj");
  EXPECT_EQ(mesh["bytes"], kQuad.size());
  EXPECT_EQ(mesh["sha256"], sha256_hex(kQuad)) << "the stored file is the OBJ, not the zip";
  EXPECT_EQ(mesh["has_uvs"], true);
  // Every file of the upload that nothing used is named; macOS's are not files of the user's.
  EXPECT_EQ(mesh["warnings"], json::array({"files of the upload not used: readme.txt"}));
  ASSERT_EQ(mesh["textures"].size(), 1u);
  const json& t = mesh["textures"][0];
  EXPECT_EQ(t["name"], "wood.jpg");
  EXPECT_EQ(t["mime"], "image/jpeg");
  EXPECT_EQ(t["bytes"], jpeg_.size());
  EXPECT_EQ(t["material"], "skin");
  EXPECT_EQ(t["kd"], json::array({0.5, 0.25, 1.0}));
  EXPECT_EQ(mesh["kd"], json::array({0.5, 0.25, 1.0}));
  const std::string id = mesh["id"];
  EXPECT_EQ(json::parse(call("GET", "/api/v1/meshes/" + id).body)["textures"], mesh["textures"]);

  const HttpResponse image = call("GET", "/api/v1/meshes/" + id + "/textures/0");
  ASSERT_EQ(image.status, 200);
  EXPECT_EQ(image.content_type, "image/jpeg");
  EXPECT_TRUE(image.body == jpeg_) << "the texture comes back byte for byte";
  for (const std::string n : {"1", "x", "-1", "99999999999"})
    EXPECT_EQ(call("GET", "/api/v1/meshes/" + id + "/textures/" + n).status, 404) << n;
  EXPECT_EQ(call("GET", "/api/v1/meshes/0000000000000000/textures/0").status, 404);

  // The texture is a blob of the mesh: it goes with it, and the owner's storage counts it.
  EXPECT_TRUE(fs::exists(dir_ / "data" / "blobs" / (id + ".tex0")));
  const std::string owner = mesh.at("owner");
  EXPECT_EQ(store_->mesh_bytes(owner), kQuad.size() + jpeg_.size());
  EXPECT_EQ(call("DELETE", "/api/v1/meshes/" + id).status, 204);
  EXPECT_EQ(store_->mesh_bytes(owner), 0u);
  EXPECT_FALSE(fs::exists(dir_ / "data" / "blobs" / (id + ".tex0")));
  EXPECT_FALSE(fs::exists(dir_ / "data" / "blobs" / (id + ".obj")));
}

// Assimp's spider: four materials on its faces (the MTL's fifth is on none),
// each with its own JPEG, all stored and
// served, and its Draco stream gives each face its material.
TEST_F(TextureUploadTest, SpiderKeepsEveryMaterialsTexture) {
  const fs::path dir = "/usr/share/assimp/models/OBJ";
  std::vector<std::pair<std::string, std::string>> files = {{"spider.obj", read_bytes(dir / "spider.obj")},
                                                            {"spider.mtl", read_bytes(dir / "spider.mtl")}};
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".jpg") files.emplace_back(e.path().filename().string(), read_bytes(e.path()));
  const json mesh = upload("spider.zip", make_zip(files));
  EXPECT_EQ(mesh["warnings"].dump().find("textur"), std::string::npos) << mesh["warnings"];
  // The images no material of the spider names are listed as not used.
  std::set<std::string> shown;
  for (const auto& t : mesh["textures"]) shown.insert(t["name"]);
  const std::string warnings = mesh["warnings"].dump();
  for (const auto& [name, bytes] : files)
    if (name.ends_with(".jpg")) {
      EXPECT_EQ(warnings.find(name) != std::string::npos, !shown.count(name)) << name << " " << warnings;
    }
  const std::vector<Material> mtl = parse_mtl(files[1].second);
  const ObjMaterialUse use = obj_material_use(files[0].second);
  ASSERT_EQ(mesh["materials"].size(), 4u) << mesh;
  ASSERT_EQ(mesh["textures"].size(), 4u) << "one image per material";
  EXPECT_EQ(mesh["textures"][0]["name"], "drkwood2.jpg") << "the texture on the most faces first";
  const std::string id = mesh["id"];
  for (std::size_t i = 0; i < use.names.size(); ++i) {
    const json& m = mesh["materials"][i];
    EXPECT_EQ(m["name"], use.names[i]) << "materials in the order of the ids in the Draco stream";
    EXPECT_EQ(m["faces"], use.faces.at(use.names[i]));
    const auto it = std::find_if(mtl.begin(), mtl.end(), [&](const Material& x) { return x.name == use.names[i]; });
    ASSERT_NE(it, mtl.end());
    ASSERT_TRUE(m["texture"].is_number()) << m;
    const std::size_t t = m["texture"];
    const std::string image = file_base_name(it->map_kd);
    EXPECT_EQ(mesh["textures"][t]["name"], image);
    EXPECT_EQ(mesh["textures"][t]["material"], use.names[i]);
    const HttpResponse served = call("GET", "/api/v1/meshes/" + id + "/textures/" + std::to_string(t));
    ASSERT_EQ(served.status, 200);
    EXPECT_TRUE(served.body == read_bytes(dir / image)) << image << " comes back byte for byte";
  }
  const HttpResponse drc = call("GET", "/api/v1/meshes/" + id + "/download?format=drc");
  ASSERT_EQ(drc.status, 200);
  std::map<std::uint32_t, std::size_t> per_material;
  for (const auto& f : test::draco_faces(drc.body)) {
    EXPECT_TRUE(f.one_material);
    ++per_material[f.material];
  }
  ASSERT_EQ(per_material.size(), 4u);
  for (std::size_t i = 0; i < use.names.size(); ++i)
    EXPECT_EQ(per_material[std::uint32_t(i)], mesh["materials"][i]["faces"]);
}

// glTF as it is shipped: a .gltf with its buffer in a .bin beside it, zipped.
std::string le32(std::uint32_t v) { return std::string{char(v), char(v >> 8), char(v >> 16), char(v >> 24)}; }
std::string le_floats(std::initializer_list<float> v) {
  std::string s;
  for (const float x : v) {
    std::uint32_t u;
    std::memcpy(&u, &x, 4);
    s += le32(u);
  }
  return s;
}
std::string le16s(std::initializer_list<std::uint16_t> v) {
  std::string s;
  for (const std::uint16_t x : v) s += {char(x), char(x >> 8)};
  return s;
}
// A unit square's positions (48 bytes), its uvs (32) and two triangles' uint16 indices (12).
const std::string kQuadBin =
    le_floats({0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0}) + le_floats({0, 0, 1, 0, 1, 1, 0, 1}) + le16s({0, 1, 2, 0, 2, 3});
// The square as two primitives (one triangle each), of materials 0 and 1 when `materials` is
// given; `buffer` is spliced into buffers[0], `extra` into the document.
std::string quad_gltf(const std::string& buffer, const std::string& materials = "", const std::string& extra = "") {
  const std::string m0 = materials.empty() ? "" : R"(,"material":0)", m1 = materials.empty() ? "" : R"(,"material":1)";
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":2)" +
         m0 + R"(},{"attributes":{"POSITION":0,"TEXCOORD_0":1},"indices":3)" + m1 + R"(}]}],)" +
         (materials.empty() ? "" : R"("materials":)" + materials + ",") + extra +
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"},)"
         R"({"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"},)"
         R"({"bufferView":2,"componentType":5123,"count":3,"type":"SCALAR"},)"
         R"({"bufferView":2,"byteOffset":6,"componentType":5123,"count":3,"type":"SCALAR"}],)"
         R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":32},)"
         R"({"buffer":0,"byteOffset":80,"byteLength":12}],"buffers":[{"byteLength":92)" +
         buffer + "}]}";
}

TEST_F(TextureUploadTest, GltfWithItsBinZipped) {
  const std::string gltf = quad_gltf(R"(,"uri":"scene.bin")");
  const json mesh = upload("scene.zip", make_zip({{"model/scene.gltf", gltf}, {"model/scene.bin", kQuadBin}}));
  EXPECT_EQ(mesh["name"], "scene.gltf");
  EXPECT_EQ(mesh["format"], "gltf");
  EXPECT_EQ(mesh["report"]["faces"], 2) << mesh["report"];
  EXPECT_EQ(mesh["warnings"], json::array()) << "the .bin counts as used";
  // What is stored reads without the zip: the buffer is embedded.
  const std::string id = mesh["id"];
  ASSERT_EQ(store_->list_meshes().size(), 1u);
  const std::string stored = store_->read_blob(store_->list_meshes()[0]);
  EXPECT_EQ(stored.find("scene.bin"), std::string::npos);
  EXPECT_EQ(read_mesh_bytes(stored, MeshFormat::gltf, "scene.gltf").mesh.num_faces(), 2u);
  EXPECT_EQ(call("GET", "/api/v1/meshes/" + id + "/download?format=drc").status, 200);

  // Alone, the .gltf names what to upload with it; a URI out of the zip is refused.
  EXPECT_EQ(call("DELETE", "/api/v1/meshes/" + id).status, 204);
  refused("scene.gltf", gltf, 400, "the file 'scene.bin' it names is missing: upload it together with the .gltf");
  refused("scene.zip", make_zip({{"m/scene.gltf", quad_gltf(R"(,"uri":"../scene.bin")")}, {"scene.bin", kQuadBin}}),
          400, "is refused: it leaves the .gltf's directory");
  refused("scene.zip", make_zip({{"scene.gltf", quad_gltf(R"(,"uri":"/etc/passwd")")}}), 400,
          "is refused: it is an absolute path");
}

// A .gltf as exporters ship it, zipped with its .bin and its texture in a
// folder: the texture listed with its material and served, each material's
// colour kept, nothing left unused, and the stored .gltf reads alone.
TEST_F(TextureUploadTest, GltfWithItsBinAndTextureZipped) {
  const std::string gltf = quad_gltf(
      R"(,"uri":"scene.bin")",
      R"([{"name":"wood","pbrMetallicRoughness":{"baseColorFactor":[1,0.5,0,1],"baseColorTexture":{"index":0}}},)"
      R"({"name":"blue","pbrMetallicRoughness":{"baseColorFactor":[0,0,1,1]}}])",
      R"("textures":[{"source":0}],"images":[{"uri":"maps/dark%20wood.jpg"}],)");
  const json mesh = upload(
      "scene.zip",
      make_zip({{"model/scene.gltf", gltf}, {"model/scene.bin", kQuadBin}, {"model/maps/dark wood.jpg", jpeg_}}));
  EXPECT_EQ(mesh["format"], "gltf");
  EXPECT_EQ(mesh["has_uvs"], true);
  EXPECT_EQ(mesh["warnings"], json::array()) << "the .bin and the image count as used";
  ASSERT_EQ(mesh["textures"].size(), 1u) << mesh;
  EXPECT_EQ(mesh["textures"][0]["name"], "dark wood.jpg");
  EXPECT_EQ(mesh["textures"][0]["mime"], "image/jpeg");
  EXPECT_EQ(mesh["textures"][0]["material"], "wood");
  ASSERT_EQ(mesh["materials"].size(), 2u);
  EXPECT_EQ(mesh["materials"][0]["kd"], json::array({1.0, 0.5, 0.0}));
  EXPECT_EQ(mesh["materials"][0]["texture"], 0);
  EXPECT_EQ(mesh["materials"][1]["kd"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(mesh["materials"][1]["texture"], nullptr);
  const std::string id = mesh["id"];
  const HttpResponse image = call("GET", "/api/v1/meshes/" + id + "/textures/0");
  ASSERT_EQ(image.status, 200);
  EXPECT_EQ(image.content_type, "image/jpeg");
  EXPECT_TRUE(image.body == jpeg_);
  const std::string stored = store_->read_blob(store_->list_meshes()[0]);
  EXPECT_EQ(stored.find("dark%20wood.jpg"), std::string::npos);
  const ReadResult alone = read_mesh_bytes(stored, MeshFormat::gltf, "scene.gltf");
  ASSERT_EQ(alone.textures.size(), 1u);
  EXPECT_TRUE(alone.textures[0].bytes == jpeg_);

  // Without the image: the mesh and its colours, and a warning naming what to upload.
  EXPECT_EQ(call("DELETE", "/api/v1/meshes/" + id).status, 204);
  const json bare = upload("scene.zip", make_zip({{"model/scene.gltf", gltf}, {"model/scene.bin", kQuadBin}}));
  EXPECT_EQ(bare["textures"], json::array());
  EXPECT_EQ(bare["materials"][0]["kd"], json::array({1.0, 0.5, 0.0}));
  ASSERT_EQ(bare["warnings"].size(), 1u) << bare;
  EXPECT_NE(bare["warnings"][0].get<std::string>().find(
                "the file 'maps/dark wood.jpg' it names is missing: upload it together with the .gltf"),
            std::string::npos)
      << bare["warnings"];
}

// A .glb with an embedded PNG and two materials of different colours: the
// texture is listed and served, each face keeps its material's colour.
TEST_F(TextureUploadTest, GlbWithAnEmbeddedTextureAndTwoMaterials) {
  const std::string png = std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR\0\0\0\1\0\0\0\1\x08\x02\0\0\0", 29);
  std::string json_text = quad_gltf(
      "",
      R"([{"name":"red","pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1],"baseColorTexture":{"index":0}}},)"
      R"({"name":"blue","pbrMetallicRoughness":{"baseColorFactor":[0,0,1,1]}}])",
      R"("textures":[{"source":0}],"images":[{"bufferView":3,"mimeType":"image/png"}],)");
  // The image's bufferView after the square's bytes (92), and the buffer grown to hold it.
  const std::string views_end = R"({"buffer":0,"byteOffset":80,"byteLength":12}])";
  json_text.replace(json_text.find(views_end), views_end.size(),
                    R"({"buffer":0,"byteOffset":80,"byteLength":12},{"buffer":0,"byteOffset":92,"byteLength":29}])");
  json_text.replace(json_text.find(R"("byteLength":92})"), 16, R"("byteLength":121})");
  while (json_text.size() % 4) json_text += ' ';
  std::string bin = kQuadBin + png;
  while (bin.size() % 4) bin += '\0';
  const std::string glb = "glTF" + le32(2) + le32(std::uint32_t(28 + json_text.size() + bin.size())) +
                          le32(std::uint32_t(json_text.size())) + "JSON" + json_text + le32(std::uint32_t(bin.size())) +
                          std::string("BIN\0", 4) + bin;
  const json mesh = upload("two.glb", glb);
  EXPECT_EQ(mesh["has_uvs"], true);
  EXPECT_EQ(mesh["warnings"], json::array());
  ASSERT_EQ(mesh["textures"].size(), 1u) << mesh;
  EXPECT_EQ(mesh["textures"][0]["name"], "image0.png");
  EXPECT_EQ(mesh["textures"][0]["mime"], "image/png");
  EXPECT_EQ(mesh["textures"][0]["material"], "red");
  ASSERT_EQ(mesh["materials"].size(), 2u);
  EXPECT_EQ(mesh["materials"][0]["name"], "red");
  EXPECT_EQ(mesh["materials"][0]["kd"], json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(mesh["materials"][0]["texture"], 0);
  EXPECT_EQ(mesh["materials"][1]["name"], "blue");
  EXPECT_EQ(mesh["materials"][1]["kd"], json::array({0.0, 0.0, 1.0}));
  EXPECT_EQ(mesh["materials"][1]["texture"], nullptr);
  EXPECT_EQ(mesh["kd"], json::array({1.0, 0.0, 0.0}));
  const std::string id = mesh["id"];
  const HttpResponse image = call("GET", "/api/v1/meshes/" + id + "/textures/0");
  ASSERT_EQ(image.status, 200);
  EXPECT_EQ(image.content_type, "image/png");
  EXPECT_TRUE(image.body == png);
  // The Draco stream gives each face its material, as an OBJ's usemtl groups.
  const HttpResponse drc = call("GET", "/api/v1/meshes/" + id + "/download?format=drc");
  ASSERT_EQ(drc.status, 200);
  std::map<std::uint32_t, std::size_t> per_material;
  for (const auto& f : test::draco_faces(drc.body)) ++per_material[f.material];
  EXPECT_EQ(per_material, (std::map<std::uint32_t, std::size_t>{{0, 1}, {1, 1}}));
}

TEST_F(TextureUploadTest, MissingImageIsAWarning) {
  const json mesh = upload("quad.zip", make_zip({{"quad.obj", kQuad}, {"quad.mtl", kMtl}}));
  EXPECT_EQ(mesh["has_uvs"], true);
  EXPECT_EQ(mesh["textures"], json::array());
  ASSERT_EQ(mesh["warnings"].size(), 1u);
  EXPECT_NE(mesh["warnings"][0].get<std::string>().find("'.\\Maps\\WOOD.JPG' is not in the upload"), std::string::npos)
      << mesh["warnings"];
  // A name that is not UTF-8 (an MTL saved in Latin-1): the upload is kept, the name quoted with U+FFFD for the byte.
  const json latin1 = upload(
      "quad.zip", make_zip({{"quad.obj", kQuad}, {"quad.mtl", "newmtl skin\nKd 0.5 0.25 1\nmap_Kd bois\xe9.jpg\n"}}));
  EXPECT_NE(latin1["warnings"].dump().find("'bois\xef\xbf\xbd.jpg' is not in the upload"), std::string::npos)
      << latin1["warnings"];
  // Not a PNG or JPEG: also a warning.
  const json gif = upload("quad.zip", make_zip({{"quad.obj", kQuad}, {"quad.mtl", kMtl}, {"wood.jpg", "GIF89a...."}}));
  EXPECT_EQ(gif["textures"], json::array());
  EXPECT_NE(gif["warnings"].dump().find("not a PNG or JPEG"), std::string::npos) << gif["warnings"];
  // The OBJ alone names its MTL: the warning says how to upload it.
  const json alone = upload("quad.obj", kQuad);
  EXPECT_EQ(alone["has_uvs"], true);
  EXPECT_NE(alone["warnings"].dump().find("upload a zip"), std::string::npos) << alone["warnings"];
}

// An OBJ with texture coordinates that names no material library and no
// material, uploaded with exactly one MTL or one image, shows it, and says so;
// with several, or none, it says what it shows instead.
TEST_F(TextureUploadTest, AnObjNamingNoMaterialTakesTheUploadsOnlyOne) {
  const std::string bare =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
  auto said = [](const json& mesh, const std::string& part) {
    return mesh["warnings"].dump().find(part) != std::string::npos;
  };
  // One MTL (with one material) and its image.
  const json one = upload("quad.zip", make_zip({{"quad.obj", bare}, {"quad.mtl", kMtl}, {"maps/wood.jpg", jpeg_}}));
  ASSERT_EQ(one["textures"].size(), 1u) << one;
  EXPECT_EQ(one["textures"][0]["name"], "wood.jpg");
  EXPECT_EQ(one["materials"][0]["texture"], 0);
  EXPECT_EQ(one["kd"], json::array({0.5, 0.25, 1.0}));
  EXPECT_TRUE(said(one, "no mtllib line): the upload's only one, 'quad.mtl', is used")) << one["warnings"];
  EXPECT_TRUE(said(one, "2 faces name no material (no usemtl line before them): the library's only one, 'skin'"))
      << one["warnings"];
  EXPECT_FALSE(said(one, "not used")) << one["warnings"];
  const HttpResponse image = call("GET", "/api/v1/meshes/" + one["id"].get<std::string>() + "/textures/0");
  EXPECT_TRUE(image.body == jpeg_);
  // Only an image.
  const json png = upload("quad.zip", make_zip({{"quad.obj", bare}, {"wood.jpg", jpeg_}}));
  ASSERT_EQ(png["textures"].size(), 1u) << png;
  EXPECT_EQ(png["materials"][0]["texture"], 0);
  EXPECT_TRUE(said(png, "the upload's only image, 'wood.jpg', is used as its texture")) << png["warnings"];
  // Two images: neither is guessed, both are listed as not used.
  const json two = upload("quad.zip", make_zip({{"quad.obj", bare}, {"a.jpg", jpeg_}, {"b.jpg", jpeg_}}));
  EXPECT_EQ(two["textures"], json::array());
  EXPECT_TRUE(said(two, "name no material (no usemtl line and no mtllib line): they show a checkerboard"))
      << two["warnings"];
  EXPECT_TRUE(said(two, "files of the upload not used: a.jpg, b.jpg")) << two["warnings"];
  // Two libraries: neither is guessed.
  const json libs = upload("quad.zip", make_zip({{"quad.obj", bare}, {"a.mtl", kMtl}, {"b.mtl", kMtl}}));
  EXPECT_TRUE(said(libs, "the upload holds 2: none is used")) << libs["warnings"];
  EXPECT_TRUE(said(libs, "not used: a.mtl, b.mtl")) << libs["warnings"];
  // Alone: the checkerboard is said; a mesh without texture coordinates says nothing of materials.
  EXPECT_TRUE(said(upload("quad.obj", bare), "checkerboard"));
  EXPECT_EQ(upload("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")["warnings"], json::array());
  // A material named by usemtl that its library lacks.
  const json missing = upload("quad.zip", make_zip({{"quad.obj", "mtllib quad.mtl\n" + bare.substr(0, bare.find("f ")) +
                                                                     "usemtl bark\n" + bare.substr(bare.find("f "))},
                                                    {"quad.mtl", kMtl}}));
  EXPECT_TRUE(said(missing, "the material 'bark' of 2 faces is in no material library uploaded")) << missing;
}

TEST_F(TextureUploadTest, PlyTextureFile) {
  const std::string ply =
      "ply\nformat ascii 1.0\ncomment TextureFile wood.jpg\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\n"
      "end_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n";
  const json mesh = upload("tri.zip", make_zip({{"tri.ply", ply}, {"wood.jpg", jpeg_}}, false));
  EXPECT_EQ(mesh["has_uvs"], true);
  ASSERT_EQ(mesh["textures"].size(), 1u);
  EXPECT_EQ(mesh["textures"][0]["name"], "wood.jpg");
  EXPECT_FALSE(mesh.contains("kd"));
  // Blender's cube with s/t and no texture: UVs, no image.
  const json cube = upload("cube_uv.ply", read_bytes("/usr/share/assimp/models/PLY/cube_uv.ply"));
  EXPECT_EQ(cube["has_uvs"], true);
  EXPECT_EQ(cube["textures"], json::array());
  EXPECT_NE(cube["warnings"].dump().find("names no texture (no 'comment TextureFile' line): it shows a checkerboard"),
            std::string::npos)
      << cube["warnings"];
  // Zipped with one image, it takes it.
  const std::string bare = std::string(ply).replace(ply.find("comment TextureFile wood.jpg\n"), 29, "");
  const json zipped = upload("tri.zip", make_zip({{"tri.ply", bare}, {"wood.jpg", jpeg_}}));
  ASSERT_EQ(zipped["textures"].size(), 1u) << zipped;
  EXPECT_NE(zipped["warnings"].dump().find("the upload's only image, 'wood.jpg', is used"), std::string::npos)
      << zipped["warnings"];
  // A mesh without UVs says so.
  const json plain = upload("tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(plain["has_uvs"], false);
}

TEST_F(TextureUploadTest, MacOsArchiveUtilityZipWithSpacesInNames) {
  const std::string obj =
      "mtllib fuze.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "usemtl fuze\nf 1/1 2/2 \\\n 3/3\nf 1/1 3/3 4/4\n";
  const std::string zip =
      archive_utility_zip({{"fuze/", ""},
                           {"fuze/fuze.obj", obj},
                           {"fuze/fuze.mtl", "newmtl fuze\nmap_Kd -s 1 1 1 fuze uv.jpg\n"},
                           {"fuze/fuze uv.jpg", jpeg_},
                           {"__MACOSX/", ""},
                           {"__MACOSX/fuze/", ""},
                           {"__MACOSX/fuze/._fuze.obj", std::string("\0\5\x16\7\0\2\0\0Mac OS X", 16)},
                           {"__MACOSX/fuze/._fuze uv.jpg", std::string("\0\5\x16\7", 4)}});
  const json mesh = upload("fuze.zip", zip);
  EXPECT_EQ(mesh["name"], "fuze.obj");
  EXPECT_EQ(mesh["report"]["faces"], 2) << mesh;
  EXPECT_EQ(mesh["report"]["vertices"], 4) << mesh;
  EXPECT_EQ(mesh["has_uvs"], true);
  ASSERT_EQ(mesh["textures"].size(), 1u) << mesh;
  EXPECT_EQ(mesh["textures"][0]["name"], "fuze uv.jpg");
  EXPECT_EQ(mesh["textures"][0]["material"], "fuze");
  EXPECT_EQ(mesh["warnings"], json::array()) << "macOS's files are no files of the user's";
}

TEST_F(TextureUploadTest, RefusedZips) {
  refused("slip.zip", make_zip({{"../quad.obj", kQuad}}), 400, "unsafe path '../quad.obj'");
  refused("slip.zip", make_zip({{"quad.obj", kQuad}, {"a/../../wood.jpg", jpeg_}}), 400, "unsafe path");
  refused("slip.zip", make_zip({{"/etc/quad.obj", kQuad}}), 400, "unsafe path");
  refused("slip.zip", make_zip({{"C:\\quad.obj", kQuad}}), 400, "unsafe path");
  refused("none.zip", make_zip({{"quad.mtl", kMtl}}), 400, "no mesh file");
  refused("two.zip", make_zip({{"a.obj", kQuad}, {"b.obj", kQuad}}), 400, "several mesh files");
  refused("junk.zip", "PK\x03\x04 but not really a zip", 400, "not a readable zip");
  refused("bad.zip", make_zip({{"quad.obj", "v 0 0 0\nf 1 2 3\n"}}), 400, "quad.obj");

  // A zip bomb in small: 1 MB of zeros deflates to about a kilobyte.
  meshes_->set_max_upload_bytes(100000);
  const std::string bomb = make_zip({{"quad.obj", kQuad + std::string(1 << 20, ' ')}});
  ASSERT_LT(bomb.size(), 20000u);
  const json j = upload("bomb.zip", bomb, 413);
  EXPECT_EQ(j["error"], "payload_too_large");
  EXPECT_NE(j["detail"].get<std::string>().find("100000 bytes"), std::string::npos) << j;
  // Under the limit the same kind of zip goes in.
  EXPECT_EQ(upload("ok.zip", make_zip({{"quad.obj", kQuad}}))["name"], "quad.obj");
  // The server still answers.
  EXPECT_EQ(call("GET", "/api/v1/health").status, 200);
}

}  // namespace
}  // namespace cgview::server
