// Materials beside a mesh (io/materials.h): MTL files, an OBJ's usemtl
// groups, a PLY's TextureFile comment, and the real files of Debian's
// assimp-testmodels (the spider's five textured materials, Blender's
// cube_uv.ply with s/t texture coordinates).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>

#include "core/errors.h"
#include "draco_faces.h"
#include "io/draco_io.h"
#include "io/materials.h"
#include "io/mesh_io.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
const fs::path kAssimp = "/usr/share/assimp/models";

TEST(Materials, ParsesMtl) {
  const auto m = parse_mtl(
      "# comment\r\nnewmtl red\r\nKd 1 0 0.5\r\nmap_Kd -s 1 1 1 tex\\Red.PNG\r\n"
      "newmtl plain\nKa 0.2 0.2 0.2\nKd spectral x.rfl\n");
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].name, "red");
  ASSERT_TRUE(m[0].kd.has_value());
  EXPECT_FLOAT_EQ((*m[0].kd)[2], 0.5f);
  EXPECT_EQ(m[0].map_kd, "tex\\Red.PNG");
  EXPECT_EQ(file_base_name(m[0].map_kd), "Red.PNG");
  EXPECT_EQ(m[1].name, "plain");
  EXPECT_FALSE(m[1].kd.has_value()) << "a spectral Kd is not a colour";
  EXPECT_TRUE(m[1].map_kd.empty());
  EXPECT_TRUE(parse_mtl("Kd 1 1 1\nmap_Kd a.png\n").empty()) << "statements before newmtl belong to no material";
}

TEST(Materials, TextureNamesWithSpacesAfterTheOptions) {
  // The file is the rest of the line once the options and their arguments are read.
  const auto m = parse_mtl(
      "newmtl fuze\nmap_Kd fuze uv.jpg\n"
      "newmtl opts\nmap_Kd -s 1 1 1 -o 0.5 0.5 -clamp on -bm 0.2 my  tex.png \r\n"
      "newmtl mm\nmap_Kd -mm 0 1 -imfchan r -texres 512 -t 1 c.png\n"
      "newmtl none\nmap_Kd -blendu off\n");
  ASSERT_EQ(m.size(), 4u);
  EXPECT_EQ(m[0].map_kd, "fuze uv.jpg");
  EXPECT_EQ(m[1].map_kd, "my  tex.png");
  EXPECT_EQ(m[2].map_kd, "c.png");
  EXPECT_TRUE(m[3].map_kd.empty());
}

TEST(Materials, LinesAsReadObjReadsThem) {
  // Continued lines (a backslash at the end) and classic Mac OS line ends, as read_obj joins and splits them.
  const auto u = obj_material_use("v 0 0 0\nusemtl a\nf 1 1 \\\n 1 1\nusemtl b\nf 1 1 1\n");
  EXPECT_EQ(u.face_material, (std::vector<std::uint32_t>{0, 0, 1}));
  const auto mac = obj_material_use("mtllib m.mtl\rv 0 0 0\rusemtl a\rf 1 1 1\rusemtl b\rf 1 1 1 1\r");
  EXPECT_EQ(mac.libraries, (std::vector<std::string>{"m.mtl"}));
  EXPECT_EQ(mac.face_material, (std::vector<std::uint32_t>{0, 1, 1}));
  const auto m = parse_mtl("newmtl a\rKd 1 0 0\rmap_Kd a b.png\r");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].map_kd, "a b.png");
}

TEST(Materials, CountsFacesPerUsemtl) {
  const auto u = obj_material_use(
      "mtllib a.mtl b.mtl\nv 0 0 0\nf 1 1 1\nusemtl x\nf 1 1 1\nf 1 1 1\n  usemtl y \nf 1 1 1\nusemtl x\nf 1 1 1\n");
  EXPECT_EQ(u.libraries, (std::vector<std::string>{"a.mtl", "b.mtl"}));
  EXPECT_EQ(u.faces.at(""), 1u);
  EXPECT_EQ(u.faces.at("x"), 3u);
  EXPECT_EQ(u.faces.at("y"), 1u);
  EXPECT_EQ(u.names, (std::vector<std::string>{"", "x", "y"})) << "in order of first use";
  EXPECT_EQ(u.face_material, (std::vector<std::uint32_t>{0, 1, 1, 2, 1}));
}

TEST(Materials, PolygonsCountAsTheirTriangles) {
  // As read_obj fans them: a quad is two triangles, a pentagon three; a comment ends the corners.
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\nusemtl a\nf 1 2 3 4 # a quad\n"
      "usemtl unused\nusemtl b\nfo 1/1 2/2 3/3 4/4 5/5\nusemtl a\nf 1 2 3\n";
  const auto u = obj_material_use(obj);
  EXPECT_EQ(u.names, (std::vector<std::string>{"a", "b"})) << "a usemtl without faces is no material";
  EXPECT_EQ(u.face_material, (std::vector<std::uint32_t>{0, 0, 1, 1, 1, 0}));
  EXPECT_EQ(u.faces.at("a"), 3u);
  EXPECT_FALSE(u.faces.contains("unused"));
}

TEST(Materials, ObjLinesSplitAtTabsAndCarriageReturnsAsTheReadersSplitThem) {
  // Words are split by io/text_scanner.h's spaces: tabs, \r, \f, \v as well as ' '.
  const auto u = obj_material_use(
      "mtllib\ta.mtl \t b.mtl\r\n\tusemtl\tx\r\n\tf\t1 2 3\r\n  fo 1\f2\v3 4\r\n"
      "f\r\nf 1 2\nfoo 1 2 3\nf1 2 3\nface 1 2 3\n");
  EXPECT_EQ(u.libraries, (std::vector<std::string>{"a.mtl", "b.mtl"}));
  EXPECT_EQ(u.names, (std::vector<std::string>{"x"}));
  EXPECT_EQ(u.face_material, (std::vector<std::uint32_t>{0, 0, 0})) << "a triangle and a quad; the rest are no faces";
  const auto m = parse_mtl("newmtl\tred \r\nKd\t1\t0 0.5\r\n");
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].name, "red");
  ASSERT_TRUE(m[0].kd.has_value());
  EXPECT_FLOAT_EQ((*m[0].kd)[2], 0.5f);
}

TEST(Materials, PlyTextureFileAndImageTypes) {
  EXPECT_EQ(ply_texture_file("ply\nformat ascii 1.0\ncomment TextureFile my tex.png\nelement vertex 0\nend_header\n"),
            "my tex.png");
  EXPECT_EQ(ply_texture_file("ply\nformat ascii 1.0\nend_header\ncomment TextureFile after.png\n"), "");
  EXPECT_EQ(image_mime_type(std::string("\x89PNG\r\n\x1a\n....", 12)), "image/png");
  EXPECT_EQ(image_mime_type("\xFF\xD8\xFF\xE0"), "image/jpeg");
  EXPECT_EQ(image_mime_type("GIF89a"), "");
  EXPECT_EQ(file_base_name("./a/b.jpg"), "b.jpg");
  EXPECT_EQ(file_base_name("b.jpg"), "b.jpg");
}

TEST(Materials, AssimpSpider) {
  const fs::path obj = kAssimp / "OBJ" / "spider.obj", mtl = kAssimp / "OBJ" / "spider.mtl";
  if (!fs::exists(obj)) GTEST_FAIL() << "missing " << obj << " (install Debian's assimp-testmodels)";
  const auto use = obj_material_use(read_file_bytes(obj, 1 << 24));
  EXPECT_EQ(use.libraries, std::vector<std::string>{"spider.mtl"});
  std::size_t faces = 0;
  for (const auto& [name, n] : use.faces) faces += n;
  const Mesh mesh = read_mesh(obj);
  EXPECT_EQ(faces, mesh.num_faces()) << "every face is counted under one material";
  EXPECT_EQ(use.faces.at("BeinTex"), 952u);
  // Every face has its material: the counts per material again.
  ASSERT_EQ(use.face_material.size(), mesh.num_faces());
  EXPECT_EQ(use.names, (std::vector<std::string>{"HLeibTex", "Skin", "BeinTex", "Augentex"}))
      << "Brusttex of the MTL is on no face";
  std::map<std::string, std::size_t> per_name;
  for (const std::uint32_t m : use.face_material) ++per_name[use.names.at(m)];
  EXPECT_EQ(per_name, use.faces);
  const auto materials = parse_mtl(read_file_bytes(mtl, 1 << 20));
  ASSERT_EQ(materials.size(), 5u);
  EXPECT_EQ(materials[3].name, "BeinTex");
  EXPECT_EQ(file_base_name(materials[3].map_kd), "drkwood2.jpg");
  EXPECT_EQ(image_mime_type(read_file_bytes(kAssimp / "OBJ" / "drkwood2.jpg", 1 << 20)), "image/jpeg");
  EXPECT_TRUE(mesh.has_uvs());
  EXPECT_EQ(mesh.uv_faces.size(), mesh.num_faces()) << "OBJ's f v/vt keeps its own UV indices";
}

// Draco keeps each face's material through its own decoder, though it
// reorders faces and splits vertices: each decoded face is matched with the
// written face nearest to its centroid.
TEST(Materials, DracoKeepsTheSpidersFaceMaterials) {
  const fs::path obj = kAssimp / "OBJ" / "spider.obj";
  if (!fs::exists(obj)) GTEST_FAIL() << "missing " << obj << " (install Debian's assimp-testmodels)";
  const Mesh mesh = read_mesh(obj);
  const auto use = obj_material_use(read_file_bytes(obj, 1 << 24));
  ASSERT_EQ(use.face_material.size(), mesh.num_faces());
  const auto faces = test::draco_faces(write_draco_with_materials(mesh, use.face_material));
  ASSERT_EQ(faces.size(), mesh.num_faces());
  const auto centroid = [](const std::array<std::array<double, 3>, 3>& c) {
    return std::array<double, 3>{(c[0][0] + c[1][0] + c[2][0]) / 3, (c[0][1] + c[1][1] + c[2][1]) / 3,
                                 (c[0][2] + c[1][2] + c[2][2]) / 3};
  };
  std::vector<std::array<double, 3>> written(mesh.num_faces());
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) c[k][i] = mesh.positions[mesh.faces[f][k]][i];
    written[f] = centroid(c);
  }
  std::map<std::uint32_t, std::size_t> decoded_per_material;
  std::size_t mismatched = 0, mixed = 0;
  double worst = 0;
  for (const auto& face : faces) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) c[k][i] = face.corners[k][i];
    const auto q = centroid(c);
    std::size_t best = 0;
    double best_d = 1e300;
    for (std::size_t f = 0; f < written.size(); ++f) {
      const double d = std::hypot(written[f][0] - q[0], written[f][1] - q[1], written[f][2] - q[2]);
      if (d < best_d) best_d = d, best = f;
    }
    worst = std::max(worst, best_d);
    if (face.material != use.face_material[best]) ++mismatched;
    if (!face.one_material) ++mixed;
    ++decoded_per_material[face.material];
  }
  EXPECT_LT(worst, 0.01) << "each decoded face lies on a written one";
  EXPECT_EQ(mismatched, 0u);
  EXPECT_EQ(mixed, 0u) << "the three corners of a face have its material";
  for (std::uint32_t m = 0; m < use.names.size(); ++m)
    EXPECT_EQ(decoded_per_material[m], use.faces.at(use.names[m])) << use.names[m];
  // Without materials the stream has no material attribute.
  EXPECT_EQ(test::draco_faces(write_mesh_bytes(mesh, MeshFormat::drc)).at(0).material, test::kNoMaterial);
  EXPECT_THROW(write_draco_with_materials(mesh, std::vector<std::uint32_t>{0, 1}), InvalidInput);
}

TEST(Materials, PlyUvsFromBlender) {
  const fs::path ply = kAssimp / "PLY" / "cube_uv.ply";
  if (!fs::exists(ply)) GTEST_FAIL() << "missing " << ply << " (install Debian's assimp-testmodels)";
  const Mesh mesh = read_mesh(ply);
  ASSERT_TRUE(mesh.has_uvs());
  ASSERT_EQ(mesh.uvs.size(), 24u);
  EXPECT_FLOAT_EQ(mesh.uvs[1].u, 1.f);  // "1.000000 -1.000000 -1.000000 ... 1.000000 0.000000"
  EXPECT_FLOAT_EQ(mesh.uvs[1].v, 0.f);
  EXPECT_FLOAT_EQ(mesh.uvs[2].v, 1.f);
  // Through Draco (what the viewer gets) the UVs survive.
  const Mesh back = read_mesh_bytes(write_mesh_bytes(mesh, MeshFormat::drc), MeshFormat::drc, "cube.drc").mesh;
  ASSERT_TRUE(back.has_uvs());
  EXPECT_EQ(back.uvs.size(), back.num_vertices());
}

}  // namespace
}  // namespace cgview
