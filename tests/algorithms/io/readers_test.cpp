// Format details of each reader: the variants real files use (OFF's prefixes,
// OBJ's index forms, PLY's encodings and property names, STL's two forms),
// and format_from_name.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/mesh.h"
#include "io/mesh_io.h"
#include "gltf_quad.h"
#include "open3d_reference.h"
#include "test_support.h"

namespace cgview {
namespace {

ReadResult read(const std::string& bytes, MeshFormat f, const std::string& name = "test", const ReadOptions& o = {}) {
  return read_mesh_bytes(bytes, f, name, o);
}
ReadResult off(const std::string& s) { return read(s, MeshFormat::off, "t.off"); }
ReadResult obj(const std::string& s) { return read(s, MeshFormat::obj, "t.obj"); }
ReadResult ply(const std::string& s) { return read(s, MeshFormat::ply, "t.ply"); }
ReadResult stl(const std::string& s, const ReadOptions& o = {}) { return read(s, MeshFormat::stl, "t.stl", o); }

bool has_warning(const ReadResult& r, const std::string& part) {
  return std::any_of(r.warnings.begin(), r.warnings.end(),
                     [&](const std::string& w) { return w.find(part) != std::string::npos; });
}

// The ParseError a read throws (a failure if it throws none).
ParseError error_of(const std::string& bytes, MeshFormat f, const std::string& name) {
  try {
    read(bytes, f, name);
    ADD_FAILURE() << "no error for " << name;
  } catch (const ParseError& e) {
    return e;
  }
  return ParseError(name, "<none>", std::nullopt, std::nullopt);
}

// Little- and big-endian byte strings.
template <class T>
std::string le(T v) {
  std::string s(sizeof(T), '\0');
  std::memcpy(s.data(), &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(s.begin(), s.end());
  return s;
}
template <class T>
std::string be(T v) {
  std::string s = le(v);
  std::reverse(s.begin(), s.end());
  return s;
}

const std::vector<Vec3> kTri = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};

// ---------------------------------------------------------------------------
// OFF

TEST(ReadOff, CommentsAndBlankLinesAnywhere) {
  const ReadResult r =
      off("# a comment before the keyword\n\nOFF # after it\n# counts next\n3 1 0\n\n# vertices\n0 0 0\n1 0 0 # x\n"
          "0 1 0\n# the face\n3 0 1 2 # done\n");
  EXPECT_EQ(r.mesh.positions, kTri);
  ASSERT_EQ(r.mesh.num_faces(), 1u);
  EXPECT_EQ(r.mesh.faces[0], (Tri{0, 1, 2}));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadOff, SpacesBlankLinesAndCommentsBeforeTheKeyword) {
  for (const std::string lead : {"   ", "\t \n\n  ", " # made by hand\n\n", "\r\n  \r\n"}) {
    SCOPED_TRACE(lead);
    const ReadResult r = off(lead + "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_EQ(r.mesh.positions, kTri);
    EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}}));
  }
}

TEST(ReadOff, ClassicMacLineEndings) {
  const ReadResult r = off("OFF\r# a comment\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
  EXPECT_TRUE(r.warnings.empty());
  // Errors name the line as the file's own line ends count them.
  const ParseError e = error_of("OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 7\r", MeshFormat::off, "mac.off");
  EXPECT_EQ(e.line(), 6u) << e.what();
}

TEST(ReadOff, CountsOnTheKeywordLine) {
  const ReadResult r = off("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(r.mesh.num_vertices(), 3u);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
}

TEST(ReadOff, CoffIntegerColoursWithAndWithoutAlpha) {
  const ReadResult r = off("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 128\n0 1 0 10 20 30\n3 0 1 2\n");
  const std::vector<Color> want = {{255, 0, 0, 255}, {0, 255, 0, 128}, {10, 20, 30, 255}};
  EXPECT_EQ(r.mesh.colors, want);
}

TEST(ReadOff, CoffFloatColours) {
  const ReadResult r = off("COFF\n3 1 0\n0 0 0 1 0 0 1\n1 0 0 0 0.5 0 0.25\n0 1 0 0 0 1 1\n3 0 1 2\n");
  const std::vector<Color> want = {{255, 0, 0, 255}, {0, 128, 0, 64}, {0, 0, 255, 255}};
  EXPECT_EQ(r.mesh.colors, want);
}

TEST(ReadOff, NoffNormalsAndStoffTextureCoordinates) {
  const ReadResult n = off("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0.6 0.8\n3 0 1 2\n");
  ASSERT_EQ(n.mesh.normals.size(), 3u);
  EXPECT_EQ(n.mesh.normals[2], (Vec3f{0, 0.6f, 0.8f}));
  EXPECT_TRUE(n.mesh.normal_faces.empty());

  const ReadResult t = off("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0.25 0.75\n3 0 1 2\n");
  ASSERT_EQ(t.mesh.uvs.size(), 3u);
  EXPECT_EQ(t.mesh.uvs[2], (Vec2f{0.25f, 0.75f}));
  EXPECT_EQ(t.mesh.positions, kTri);

  // All prefixes at once, in Geomview's order: normal, colour, texture.
  const ReadResult all =
      off("STCNOFF\n3 1 0\n0 0 0 0 0 1 255 0 0 255 0.5 0.5\n1 0 0 0 0 1 0 255 0 255 1 0\n"
          "0 1 0 0 0 1 0 0 255 255 0 1\n3 0 1 2\n");
  EXPECT_EQ(all.mesh.positions, kTri);
  ASSERT_EQ(all.mesh.colors.size(), 3u);
  EXPECT_EQ(all.mesh.colors[1], (Color{0, 255, 0, 255}));
  EXPECT_EQ(all.mesh.uvs[0], (Vec2f{0.5f, 0.5f}));
  EXPECT_EQ(all.mesh.normals[2], (Vec3f{0, 0, 1}));
}

TEST(ReadOff, HomogeneousCoordinatesAreDivided) {
  const ReadResult r = off("4OFF\n3 1 0\n0 0 0 1\n2 0 0 2\n0 3 0 3\n3 0 1 2\n");
  EXPECT_EQ(r.mesh.positions, kTri);
}

TEST(ReadOff, PolygonsAreFanTriangulatedWithAWarning) {
  const ReadResult r = off("OFF\n6 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n2 1 0\n4 0 1 2 3\n4 1 4 5 2\n");
  const std::vector<Tri> want = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
  EXPECT_EQ(r.mesh.faces, want);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "2 polygons were split into triangles");

  const ReadResult pentagon = off("OFF\n5 1 0\n0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 1 0\n5 0 1 2 3 4\n");
  EXPECT_EQ(pentagon.mesh.num_faces(), 3u);
  EXPECT_TRUE(has_warning(pentagon, "1 polygons were split"));
}

TEST(ReadOff, FaceColoursAreIgnoredAndTrailingDataWarned) {
  const ReadResult r = off("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0 0\nsomething else\n");
  EXPECT_EQ(r.mesh.num_faces(), 1u);
  EXPECT_TRUE(has_warning(r, "ignored data after the last face (line 7)"));
}

TEST(ReadOff, UnderflowingCoordinatesAreZeroNotInfinite) {
  // 1e-400 is below a double's range: it is 0, not a "non-finite coordinate".
  const ReadResult r = off("OFF\n3 1 0\n1e-400 0 0\n1 -1e-400 0\n0 1 0.0000000001e-320\n3 0 1 2\n");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_TRUE(std::signbit(r.mesh.positions[1].y));
  // And overflow still is refused.
  const ParseError e = error_of("OFF\n3 1 0\n1e400 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", MeshFormat::off, "o.off");
  EXPECT_EQ(e.line(), 3u);
  EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos);
}

TEST(ReadOff, Errors) {
  struct Case {
    std::string text, says;
    std::uint64_t line;
  };
  const std::vector<Case> cases = {
      {"PLY\n3 1 0\n", "not an OFF file", 1},
      {"nOFF\n3\n3 1 0\n", "nOFF", 1},
      {"OFF BINARY\n3 1 0\n", "binary OFF is not supported", 1},
      {"OFF\n-3 1 0\n", "negative vertex or face count", 2},
      {"OFF\n3 1 0\n0 0 0\n1 0\n0 1 0\n3 0 1 2\n", "expected a vertex coordinate, found the end of the line", 4},
      {"OFF\n3 1 0\n0 0 0 7\n1 0 0\n0 1 0\n3 0 1 2\n", "unexpected '7' after vertex 0", 3},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "face 0 has 2 corners", 6},
      {"OFF\n3 1 0\n0 0 0\n1 0 0\n0 x 0\n3 0 1 2\n", "expected a vertex coordinate, found 'x'", 5},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const ParseError e = error_of(c.text, MeshFormat::off, "bad.off");
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.file(), "bad.off");
  }
}

// ---------------------------------------------------------------------------
// OBJ

TEST(ReadObj, VertexTextureNormalTriples) {
  const ReadResult r =
      obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
          "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
          "vn 0 0 1\n"
          "f 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/5/1\n");
  ASSERT_EQ(r.mesh.num_faces(), 2u);
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_EQ(r.mesh.uvs.size(), 5u);
  const std::vector<Tri> uv_faces = {{0, 1, 2}, {0, 2, 4}};
  EXPECT_EQ(r.mesh.uv_faces, uv_faces);
  ASSERT_EQ(r.mesh.normals.size(), 1u);
  const std::vector<Tri> normal_faces = {{0, 0, 0}, {0, 0, 0}};
  EXPECT_EQ(r.mesh.normal_faces, normal_faces);
  EXPECT_EQ(r.mesh.uvs[4], (Vec2f{0.5f, 0.5f}));
  EXPECT_NO_THROW(r.mesh.validate());
}

TEST(ReadObj, IndicesEqualToTheVertexIndicesBecomePerVertex) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n");
  EXPECT_EQ(r.mesh.uvs.size(), 3u);
  EXPECT_TRUE(r.mesh.uv_faces.empty());
  EXPECT_TRUE(r.mesh.attributes_per_vertex());
}

TEST(ReadObj, VertexSlashSlashNormal) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 -1\nf 1//1 2//1 3//2\n");
  EXPECT_FALSE(r.mesh.has_uvs());
  ASSERT_EQ(r.mesh.normals.size(), 2u);
  EXPECT_EQ(r.mesh.normal_faces, (std::vector<Tri>{{0, 0, 1}}));
}

TEST(ReadObj, NegativeIndicesAreRelativeToTheVerticesSoFar) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\nf 2 4 -2\n");
  const std::vector<Tri> want = {{0, 1, 2}, {1, 3, 2}, {1, 3, 2}};
  EXPECT_EQ(r.mesh.faces, want);
}

TEST(ReadObj, QuadsCommentsGroupsAndMaterialsAreHandled) {
  const ReadResult r =
      obj("# made by hand\nmtllib a.mtl\no thing\ng side\nusemtl red\ns off\n"
          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0 # a comment after a vertex\n"
          "f 1 2 3 4\ng other\ns 1\nf 1 3 4 # and after a face\n");
  const std::vector<Tri> want = {{0, 1, 2}, {0, 2, 3}, {0, 2, 3}};
  EXPECT_EQ(r.mesh.faces, want);
  EXPECT_EQ(r.warnings, std::vector<std::string>{"1 polygons were split into triangles"});
}

TEST(ReadObj, LinesPointsAndUnknownRecordsAreSkippedWithWarnings) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\np 3\nfoo bar\n");
  EXPECT_EQ(r.mesh.num_faces(), 1u);
  EXPECT_TRUE(has_warning(r, "1 line records (l) were skipped"));
  EXPECT_TRUE(has_warning(r, "1 point records (p) were skipped"));
  EXPECT_TRUE(has_warning(r, "1 records of unknown kinds were skipped"));
}

// A file from a CAD tool: groups, a line, parameter-space vertices and a
// free-form curve between the polygons.  The polygons are read whole; what
// holds geometry and is not read is said.
TEST(ReadObj, GroupsLinesAndFreeFormRecordsMixedIn) {
  const ReadResult r =
      obj("g part1\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvp 0.5 0.5\nvp 0.2\nl 1 2\n"
          "cstype bspline\ndeg 2\ncurv 0 1 1 2 3\nparm u 0 0 0 1 1 1\nend\ng part2\nf 1 2 3\n"
          "g part3\nf 2 4 3\n");
  EXPECT_EQ(r.mesh.num_vertices(), 4u);
  const std::vector<Tri> want = {{0, 1, 2}, {1, 3, 2}};
  EXPECT_EQ(r.mesh.faces, want);
  EXPECT_TRUE(has_warning(r, "1 line records (l) were skipped"));
  EXPECT_TRUE(has_warning(
      r, "7 free-form curve and surface records (vp, curv, surf, ...) were skipped: only polygons are read"));
  EXPECT_FALSE(has_warning(r, "unknown"));
}

TEST(ReadObj, VertexColours) {
  const ReadResult r = obj("v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0.5 1\nf 1 2 3\n");
  const std::vector<Color> want = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 128, 255, 255}};
  EXPECT_EQ(r.mesh.colors, want);
  EXPECT_EQ(r.mesh.positions, kTri);
  // Only some vertices coloured: dropped with a warning.
  const ReadResult some = obj("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_FALSE(some.mesh.has_colors());
  EXPECT_TRUE(has_warning(some, "vertex colours dropped"));
  // A homogeneous w is not a colour.
  const ReadResult w = obj("v 0 0 0 1\nv 1 0 0 1\nv 0 1 0 1\nf 1 2 3\n");
  EXPECT_FALSE(w.mesh.has_colors());
  EXPECT_EQ(w.mesh.positions, kTri);
}

TEST(ReadObj, FacesWithAndWithoutTextureCoordinatesDropThemWithAWarning) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nf 2 4 3\n");
  EXPECT_EQ(r.mesh.num_faces(), 2u);
  EXPECT_FALSE(r.mesh.has_uvs());
  EXPECT_TRUE(r.mesh.uv_faces.empty());
  EXPECT_TRUE(has_warning(r, "texture coordinates dropped: some faces have them and others do not"));
  EXPECT_NO_THROW(r.mesh.validate());
  // The same for normals.
  const ReadResult n = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n");
  EXPECT_FALSE(n.mesh.has_normals());
  EXPECT_TRUE(has_warning(n, "normals dropped"));
}

TEST(ReadObj, WindowsLineEndings) {
  const ReadResult r = obj("v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nvt 0 0\r\nf 1/1 2/1 3/1\r\n");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
}

TEST(ReadObj, ClassicMacLineEndings) {
  const ReadResult r = obj("# from an old Mac\r\rv 0 0 0\rv 1 0 0\rv 0 1 0\rvt 0 0\rf 1/1 2/1 3/1\r");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadObj, BackslashContinuesALine) {
  const ReadResult r =
      obj("v 0 0 \\\n0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
          "# a comment's last backslash continues nothing: C:\\path\\\n"
          "f 1 2 \\\n   3\n"
          "f 2 \\  \r\n4 \\\n 3\n");
  EXPECT_EQ(r.mesh.num_vertices(), 4u);
  EXPECT_EQ(r.mesh.positions[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(r.mesh.positions[3], (Vec3{1, 1, 0}));
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {1, 3, 2}}));
  EXPECT_TRUE(r.warnings.empty());
  // Lines after a continued one keep their numbers.
  const ParseError e = error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 3\nf 1 2 9\n", MeshFormat::obj, "bad.obj");
  EXPECT_EQ(e.line(), 6u) << e.what();
  // A backslash on the last line, with nothing to continue with, is an error as before.
  EXPECT_NE(std::string(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 \\", MeshFormat::obj, "end.obj").what())
                .find("found '\\'"),
            std::string::npos);
}

TEST(ReadObj, Errors) {
  struct Case {
    std::string text, says;
    std::optional<std::uint64_t> line;
  };
  const std::vector<Case> cases = {
      {"", "no vertices and no faces", std::nullopt},
      {"# only a comment\n", "no vertices and no faces", std::nullopt},
      {"v 0 0\n", "expected a vertex coordinate", 1},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "a face has 2 corners", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "face 0 refers to vertex 4 but 3 are defined before it", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "face 0 refers to vertex -4", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1\n", "refers to texture coordinate 1 but 0", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/x\n", "expected a face corner", 4},
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3/1/1/1\n", "more than three parts", 4},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const ParseError e = error_of(c.text, MeshFormat::obj, "bad.obj");
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), c.line) << e.what();
    EXPECT_EQ(e.file(), "bad.obj");
  }
}

// ---------------------------------------------------------------------------
// PLY

const char* kPlyHead = "ply\nformat ascii 1.0\ncomment made by hand\nobj_info nothing\n";

TEST(ReadPly, AsciiWithUcharColoursAndNormals) {
  const ReadResult r = ply(std::string(kPlyHead) +
                           "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                           "property float nx\nproperty float ny\nproperty float nz\n"
                           "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0 0 0 1 255 0 0\n1 0 0 0 0 1 0 255 0\n0 1 0 0 0 1 1 2 3\n3 0 1 2\n");
  EXPECT_EQ(r.mesh.positions, kTri);
  const std::vector<Color> want = {{255, 0, 0, 255}, {0, 255, 0, 255}, {1, 2, 3, 255}};
  EXPECT_EQ(r.mesh.colors, want);
  ASSERT_EQ(r.mesh.normals.size(), 3u);
  EXPECT_EQ(r.mesh.normals[0], (Vec3f{0, 0, 1}));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadPly, FloatColoursAndDiffuseNamesAndAlpha) {
  const ReadResult r = ply(std::string(kPlyHead) +
                           "element vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
                           "property float diffuse_red\nproperty float diffuse_green\nproperty float diffuse_blue\n"
                           "property float alpha\n"
                           "element face 1\nproperty list uchar uint vertex_index\nend_header\n"
                           "0 0 0 1 0 0 1\n1 0 0 0 0.5 0 0.5\n0 1 0 0 0 1 0\n3 0 1 2\n");
  const std::vector<Color> want = {{255, 0, 0, 255}, {0, 128, 0, 128}, {0, 0, 255, 0}};
  EXPECT_EQ(r.mesh.colors, want);
  ASSERT_EQ(r.mesh.num_faces(), 1u);  // read through "vertex_index"
}

TEST(ReadPly, ExtraElementsAndPropertiesAreSkipped) {
  const ReadResult r =
      ply(std::string(kPlyHead) +
          "element material 1\nproperty uchar ambient_red\nproperty list uchar float coefficients\n"
          "element vertex 3\nproperty float x\nproperty int flags\nproperty float y\nproperty float z\n"
          "property list uchar float extra\n"
          "element face 1\nproperty uchar kind\nproperty list uchar int vertex_indices\n"
          "property list uchar float weights\n"
          "element edge 2\nproperty int vertex1\nproperty int vertex2\nend_header\n"
          "7 2 0.5 0.25\n"
          "0 9 0 0 0\n1 9 0 0 1 5\n0 9 1 0 2 5 6\n"
          "4 3 0 1 2 2 1 1\n"
          "0 1\n1 2\n");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}}));
  EXPECT_TRUE(has_warning(r, "skipped 1 'material' elements"));
  EXPECT_TRUE(has_warning(r, "skipped 2 'edge' elements"));
}

// A binary PLY body: x y z as float, red green blue as uchar, faces as uchar count + int indices.
std::string binary_ply_body(bool big) {
  auto f = [&](float v) { return big ? be(v) : le(v); };
  auto i = [&](std::int32_t v) { return big ? be(v) : le(v); };
  std::string s;
  const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const unsigned char rgb[3][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}};
  for (int v = 0; v < 3; ++v) {
    for (float c : xyz[v]) s += f(c);
    for (unsigned char c : rgb[v]) s += char(c);
  }
  s += char(4) + i(0) + i(1) + i(2) + i(0);  // a quad of 3 vertices (0 1 2 0): two triangles
  return s;
}
std::string binary_ply(bool big) {
  return std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
         " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
         "property uchar red\nproperty uchar green\nproperty uchar blue\n"
         "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
         binary_ply_body(big);
}

TEST(ReadPly, BinaryLittleAndBigEndianReadTheSame) {
  for (bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    const ReadResult r = ply(binary_ply(big));
    EXPECT_EQ(r.mesh.positions, kTri);
    const std::vector<Color> want = {{255, 0, 0, 255}, {0, 255, 0, 255}, {0, 0, 255, 255}};
    EXPECT_EQ(r.mesh.colors, want);
    EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 0}}));
    EXPECT_TRUE(has_warning(r, "1 polygons were split into triangles"));
  }
  // Big-endian doubles and ushort counts too.
  std::string s =
      "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
      "property double z\nelement face 1\nproperty list ushort uint vertex_indices\nend_header\n";
  for (const Vec3& p : kTri) s += be(p.x) + be(p.y) + be(p.z);
  s += be(std::uint16_t(3)) + be(std::uint32_t(2)) + be(std::uint32_t(1)) + be(std::uint32_t(0));
  const ReadResult r = ply(s);
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{2, 1, 0}}));
}

TEST(ReadPly, AsciiFloatPropertiesAreFloats) {
  // "0.1" in a float property is 0.1f, as the same file in binary would hold.
  const ReadResult r = ply(std::string(kPlyHead) +
                           "element vertex 3\nproperty float x\nproperty float y\nproperty double z\n"
                           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0.1 0 0.1\n1 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(r.mesh.positions[0].x, double(0.1f));
  EXPECT_EQ(r.mesh.positions[0].z, 0.1);
}

TEST(ReadPly, MeshLabPerCornerTexcoords) {
  const ReadResult r =
      ply(std::string(kPlyHead) +
          "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
          "end_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n"
          "3 0 1 2 6 0 0 1 0 1 1\n3 0 2 3 6 0 0 0.5 0.5 0 1\n");
  ASSERT_EQ(r.mesh.num_faces(), 2u);
  ASSERT_EQ(r.mesh.uv_faces.size(), 2u);
  ASSERT_EQ(r.mesh.uvs.size(), 6u);
  const Tri t = r.mesh.uv_faces[1];
  EXPECT_EQ(r.mesh.uvs[t[0]], (Vec2f{0, 0}));
  EXPECT_EQ(r.mesh.uvs[t[1]], (Vec2f{0.5f, 0.5f}));
  EXPECT_EQ(r.mesh.uvs[t[2]], (Vec2f{0, 1}));
  EXPECT_NO_THROW(r.mesh.validate());
  // Per-vertex s t win over per-corner texcoords.
  const ReadResult both =
      ply(std::string(kPlyHead) +
          "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "property float s\nproperty float t\n"
          "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
          "end_header\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2 6 9 9 9 9 9 9\n");
  EXPECT_TRUE(both.mesh.uv_faces.empty());
  EXPECT_EQ(both.mesh.uvs[2], (Vec2f{0, 1}));
  // A texcoord list of the wrong length drops the per-corner UVs with a warning.
  const ReadResult bad =
      ply(std::string(kPlyHead) +
          "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 1\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
          "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 4 0 0 1 0\n");
  EXPECT_FALSE(bad.mesh.has_uvs());
  EXPECT_TRUE(has_warning(bad, "per-corner texture coordinates dropped"));
}

TEST(ReadPly, OtherFaceListsAreSkippedInBinary) {
  // A texcoord list after the indices and another list before them, in either byte order.
  for (bool big : {false, true}) {
    SCOPED_TRACE(big ? "big endian" : "little endian");
    auto f = [&](float v) { return big ? be(v) : le(v); };
    auto i = [&](std::int32_t v) { return big ? be(v) : le(v); };
    std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "element face 2\nproperty list uchar int flags\nproperty list uchar int vertex_indices\n"
                    "property list uchar float texcoord\nproperty int texnumber\nend_header\n";
    for (const Vec3f p : {Vec3f{0, 0, 0}, Vec3f{1, 0, 0}, Vec3f{1, 1, 0}, Vec3f{0, 1, 0}})
      s += f(p.x) + f(p.y) + f(p.z);
    s += char(1) + i(7) + char(3) + i(0) + i(1) + i(2) + char(6) + f(0) + f(0) + f(1) + f(0) + f(1) + f(1) + i(0);
    s += std::string(1, '\0') + char(3) + i(0) + i(2) + i(3) + char(6) + f(0) + f(0) + f(1) + f(1) + f(0.5f) + f(1) +
         i(0);
    const ReadResult r = ply(s);
    EXPECT_EQ(r.mesh.num_vertices(), 4u);
    EXPECT_EQ(r.mesh.positions[2], (Vec3{1, 1, 0}));
    EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
    ASSERT_EQ(r.mesh.uv_faces.size(), 2u);
    EXPECT_EQ(r.mesh.uvs[r.mesh.uv_faces[1][2]], (Vec2f{0.5f, 1}));
  }
}

TEST(ReadPly, ClassicMacAndWindowsLineEndings) {
  const std::string head =
      "ply\nformat ascii 1.0\ncomment old Mac\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  for (const std::string eol : {"\r", "\r\n"}) {
    SCOPED_TRACE(eol == "\r" ? "\\r" : "\\r\\n");
    std::string text = head + body;
    std::string with;
    for (char c : text) with += c == '\n' ? eol : std::string(1, c);
    const ReadResult r = ply(with);
    EXPECT_EQ(r.mesh.positions, kTri);
    EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}}));
  }
  // A binary body after a "\r" header: its first bytes are a '\n' and a '\r', data, not line ends.
  std::string bin =
      "ply\rformat binary_little_endian 1.0\relement vertex 3\rproperty uchar flag\rproperty float x\r"
      "property float y\rproperty float z\relement face 1\rproperty list uchar int vertex_indices\rend_header\r";
  const unsigned char flags[3] = {'\n', '\r', 7};
  for (int v = 0; v < 3; ++v)
    bin += char(flags[v]) + le(float(kTri[v].x)) + le(float(kTri[v].y)) + le(float(kTri[v].z));
  bin += char(3) + le(std::int32_t(0)) + le(std::int32_t(1)) + le(std::int32_t(2));
  const ReadResult r = ply(bin);
  EXPECT_EQ(r.mesh.positions, kTri);
  ASSERT_EQ(r.properties.size(), 1u);
  EXPECT_EQ(r.properties[0].values, (std::vector<float>{10, 13, 7}));
  // Errors count "\r" lines.
  const ParseError e = error_of("ply\rformat ascii 1.0\rwhatever\rend_header\r", MeshFormat::ply, "mac.ply");
  EXPECT_EQ(e.line(), 3u) << e.what();
  EXPECT_NE(std::string(e.what()).find("unknown header line 'whatever'"), std::string::npos) << e.what();
}

TEST(ReadPly, PointCloudLoadsWithoutFaces) {
  const ReadResult r = ply(std::string(kPlyHead) +
                           "element vertex 2\nproperty float x\nproperty float y\n"
                           "property float z\nend_header\n1 2 3\n4 5 6\n");
  EXPECT_EQ(r.mesh.num_vertices(), 2u);
  EXPECT_EQ(r.mesh.num_faces(), 0u);
}

// The same 64 points as Open3D, meshio and draco_encoder wrote them
// (tests/data/points/README.md), read by us and by Open3D.
const std::filesystem::path kPoints = CGVIEW_POINTS_DATA_DIR;

TEST(ReadPointClouds, FilesThatOtherToolsWroteReadAsOpen3DReadsThem) {
  ASSERT_TRUE(test::have_open3d()) << "/usr/bin/python3 has no open3d (install Debian's python3-open3d)";
  std::string log;
  const auto ref = test::open3d_read(kPoints / "sphere_open3d.ply", "auto", &log);
  ASSERT_TRUE(ref) << log;
  ASSERT_EQ((*ref)["points"].size(), 64u);
  struct Case {
    const char* file;
    bool normals, colors;
    double tol;  // the text files' 10 decimals; Draco's quantized positions (under 8e-4 seen)
  };
  for (const Case c : {Case{"sphere_open3d.ply", true, true, 1e-6}, Case{"sphere_open3d.xyz", true, false, 1e-9},
                       Case{"sphere_open3d.pts", false, true, 1e-9}, Case{"sphere_draco.drc", true, false, 1e-3}}) {
    SCOPED_TRACE(c.file);
    const ReadResult r = read_mesh_file(kPoints / c.file);
    EXPECT_EQ(r.mesh.num_faces(), 0u);
    ASSERT_EQ(r.mesh.num_vertices(), 64u);
    EXPECT_EQ(r.mesh.normals.size(), c.normals ? 64u : 0u);
    EXPECT_EQ(r.mesh.colors.size(), c.colors ? 64u : 0u);
    // Draco's kd-tree (draco_encoder's choice) reorders the points: each is
    // matched to Open3D's nearest, and no two to the same.
    std::vector<bool> taken(64, false);
    for (std::size_t i = 0; i < 64; ++i) {
      std::size_t best = 0;
      double best_d = 1e300;
      for (std::size_t j = 0; j < 64; ++j) {
        const auto& q = (*ref)["points"][j];
        const double d = norm(r.mesh.positions[i] - Vec3{q[0].get<double>(), q[1].get<double>(), q[2].get<double>()});
        if (d < best_d) best_d = d, best = j;
      }
      EXPECT_LE(best_d, c.tol) << i;
      EXPECT_FALSE(taken[best]) << i;
      taken[best] = true;
      for (int k = 0; c.normals && k < 3; ++k)
        EXPECT_NEAR(r.mesh.normals[i][k], (*ref)["normals"][best][k].get<double>(), 1e-2) << i;
      if (c.colors) {
        EXPECT_NEAR(r.mesh.colors[i].r, (*ref)["colors"][best][0].get<double>() * 255, 0.5) << i;
      }
    }
  }
}

TEST(ReadPointClouds, XyzRowsWithAndWithoutNormals) {
  const ReadResult r = read("# a scan\n0 0 0\n1 2.5 -3e2\n\n  4 5 6 # last\n", MeshFormat::xyz, "s.xyz");
  ASSERT_EQ(r.mesh.num_vertices(), 3u);
  EXPECT_EQ(r.mesh.positions[1], (Vec3{1, 2.5, -300}));
  EXPECT_TRUE(r.mesh.normals.empty());
  const ReadResult n = read("0 0 0 0 0 1\r\n1 1 1 1 0 0\r\n", MeshFormat::xyz, "n.xyz");
  ASSERT_EQ(n.mesh.normals.size(), 2u);
  EXPECT_EQ(n.mesh.normals[1], (Vec3f{1, 0, 0}));
}

TEST(ReadPointClouds, PtsScansWithIntensityAndColours) {
  // Two scans, each with its count; the intensities are dropped with a word.
  const ReadResult r = read("2\n0 0 0 -1200 255 0 0\n1 0 0 30 0 255 0\n1\n0 1 0 7 0 0 255\n", MeshFormat::pts, "s.pts");
  ASSERT_EQ(r.mesh.num_vertices(), 3u);
  ASSERT_EQ(r.mesh.colors.size(), 3u);
  EXPECT_EQ(r.mesh.colors[2].b, 255);
  EXPECT_EQ(r.mesh.colors[1].g, 255);
  EXPECT_TRUE(has_warning(r, "intensities are not kept"));
  const ReadResult plain = read("1\n1 2 3\n", MeshFormat::pts, "p.pts");
  EXPECT_EQ(plain.mesh.positions[0], (Vec3{1, 2, 3}));
  EXPECT_TRUE(plain.warnings.empty());
}

TEST(ReadPointClouds, ObjOfVerticesAndTheirNormals) {
  const ReadResult r = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 1\nvn 1 0 0\n");
  EXPECT_EQ(r.mesh.num_faces(), 0u);
  ASSERT_EQ(r.mesh.normals.size(), 3u);
  EXPECT_EQ(r.mesh.normals[2], (Vec3f{1, 0, 0}));
  const ReadResult odd = obj("v 0 0 0\nv 1 0 0\nvn 0 0 1\n");
  EXPECT_TRUE(odd.mesh.normals.empty());
  EXPECT_TRUE(has_warning(odd, "not one per vertex"));
}

TEST(ReadPointClouds, PlyOfVerticesWithNormalsAndColours) {
  const ReadResult r = ply(std::string(kPlyHead) +
                           "element vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                           "property float nx\nproperty float ny\nproperty float nz\nproperty uchar red\n"
                           "property uchar green\nproperty uchar blue\nend_header\n"
                           "1 2 3 0 0 1 255 0 0\n4 5 6 1 0 0 0 0 255\n");
  EXPECT_EQ(r.mesh.num_faces(), 0u);
  ASSERT_EQ(r.mesh.normals.size(), 2u);
  EXPECT_EQ(r.mesh.normals[1], (Vec3f{1, 0, 0}));
  ASSERT_EQ(r.mesh.colors.size(), 2u);
  EXPECT_EQ(r.mesh.colors[1].b, 255);
}

TEST(ReadPointClouds, Errors) {
  struct Case {
    std::string bytes;
    MeshFormat format;
    std::string says;
    std::uint64_t line;
  };
  const std::vector<Case> cases = {
      {"", MeshFormat::xyz, "no points", 1},
      {"1 2 3\n4 5\n", MeshFormat::xyz, "a row of 2 numbers", 2},
      {"1 2 3\n4 5 6 0 0 1\n", MeshFormat::xyz, "a row of 6 numbers after rows of 3", 2},
      {"1,2,3\n", MeshFormat::xyz, "expected a number, found '1,2,3'", 1},
      {"1 2 nan\n", MeshFormat::xyz, "non-finite", 1},
      {"0 0 0 0 0 0 0\n", MeshFormat::xyz, "more than 6 numbers", 1},
      {"2\n1 2 3\n# cut short\n", MeshFormat::pts, "ends after 1 of its 2 points", 4},
      {"99999999\n1 2 3\n", MeshFormat::pts, "claims 99999999 points", 1},
      {"1 2 3\n", MeshFormat::pts, "the number of points alone", 1},
      {"1\n1 2 3 4 5\n", MeshFormat::pts, "a row of 5 numbers", 2},
      {"1\n1 2 3 0 300 0 0\n", MeshFormat::pts, "outside 0..255", 2},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.bytes);
    const ParseError e = error_of(c.bytes, c.format, c.format == MeshFormat::xyz ? "s.xyz" : "s.pts");
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), c.line) << e.what();
  }
}

// The fuzzer's findings: a Draco cloud whose header claims 2 billion points,
// or of an old kd-tree bitstream, is refused before Draco allocates for them, and a coordinate that is a
// double but no float is refused by the Draco writer (the viewer's stream).
TEST(ReadPointClouds, HostileDracoCloudsAndCoordinatesPastAFloat) {
  // DRACO 2.2, a point cloud, sequential; 2^31 - 1 points; one decoder of one
  // float32 attribute of 3 components.
  std::string claim = std::string("DRACO") + '\x02' + '\x02' + '\x00' + '\x00' + '\x00' + '\x00';
  claim += le(std::uint32_t(0x7fffffff));
  claim += std::string("\x01\x01\x00\x09\x03\x00\x00", 7) + std::string(16, '\0');
  const ParseError e = error_of(claim, MeshFormat::drc, "claim.drc");
  EXPECT_NE(std::string(e.what()).find("claims 2147483647 points of 3 components"), std::string::npos) << e.what();
  // DRACO 2.0, a kd-tree point cloud (tests/fuzz/corpus/drc/regression-old-kd-tree):
  // the old bitstream's second count of points, 0xffff0101, went to Draco's
  // allocation unchecked (4 GB for 51 bytes).
  const std::string old_kd_tree(
      "\x44\x52\x41\x43\x4f\x02\x00\x00\x01\xbf\x02\x09\x01\xff\x01\x01\x01\x01\x01\x01\x01\x01\x01\x01"
      "\x01\x01\xff\xff\xff\xff\x0f\x01\x00\x01\x01\x81\x01\x32\x01\x01\x01\x02\x02\x01\x01\x01\x01\x01"
      "\x01\x01\xff",
      51);
  const ParseError old = error_of(old_kd_tree, MeshFormat::drc, "old.drc");
  EXPECT_NE(std::string(old.what()).find("a kd-tree Draco point cloud of a bitstream before 2.3"), std::string::npos)
      << old.what();
  const Mesh far = read("0 0 0\n1 2 1e308\n", MeshFormat::xyz, "far.xyz").mesh;
  try {
    write_mesh_bytes(far, MeshFormat::drc);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 1 lies beyond the range of a float"), std::string::npos) << e.what();
  }
}

// Triangle strips as Stanford's scans store them: a 2 x 1 grid of squares as
// one strip (0 3 1 4 2 5), a -1, then a second strip whose two runs are
// joined by repeated corners (the join's triangles are left out).  The expected
// triangles are the strip's definition written out: corner k with the two
// before it, every other one turned, so all face the same way.
TEST(ReadPly, TriangleStripsAreReadAsMeshLabReadsThem) {
  const std::string head =
      "element vertex 6\nproperty float x\nproperty float y\nproperty float z\n"
      "element tristrips 1\nproperty list int int vertex_indices\nend_header\n";
  const std::string verts = "0 0 0\n1 0 0\n2 0 0\n0 1 0\n1 1 0\n2 1 0\n";
  const std::vector<int> strip = {0, 3, 1, 4, 2, 5, -1, 0, 1, 3, 3, 3, 4, 1, 2};
  std::string ascii = std::string(kPlyHead) + head + verts + std::to_string(strip.size());
  for (int i : strip) ascii.append(1, ' ').append(std::to_string(i));
  const ReadResult a = ply(ascii + "\n");
  const std::vector<Tri> want = {{0, 3, 1}, {1, 3, 4}, {1, 4, 2}, {2, 4, 5},  // the first strip
                                 {0, 1, 3},                                   // the second's first run
                                 {3, 4, 1}, {1, 4, 2}};                       // its second, after (3 3 3 4)
  EXPECT_EQ(a.mesh.faces, want);
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_EQ(
      a.warnings[0],
      "read 2 triangle strips into triangles (3 triangles with a repeated corner, which only join strips, left out)");
  // Binary, with uint indices and a uchar count: the same triangles.
  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
      "property float z\nelement tristrips 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 6; ++v) {
    const float xyz[3] = {float(v % 3), float(v / 3), 0.f};
    bin.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
  }
  bin += char(strip.size());
  for (int i : strip) bin.append(reinterpret_cast<const char*>(&i), 4);
  EXPECT_EQ(ply(bin).mesh.faces, want);
  // Each triangle of the first strip faces the same way (+z or -z alike).
  for (std::size_t f = 0; f < 4; ++f) {
    const auto& p = a.mesh.positions;
    const auto& t = a.mesh.faces[f];
    const double z =
        (p[t[1]][0] - p[t[0]][0]) * (p[t[2]][1] - p[t[0]][1]) - (p[t[1]][1] - p[t[0]][1]) * (p[t[2]][0] - p[t[0]][0]);
    EXPECT_LT(z, 0) << "triangle " << f;
  }
  // An index past the vertices names the strip.
  EXPECT_THROW(ply(std::string(kPlyHead) + head + verts + "3 0 1 6\n"), ParseError);
}

TEST(ReadPly, Errors) {
  const std::string v3 = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string f1 = "element face 1\nproperty list uchar int vertex_indices\n";
  struct Case {
    std::string text, says;
    std::optional<std::uint64_t> line;
  };
  const std::vector<Case> cases = {
      {"PLY\n", "not a PLY file", 1},
      {"ply\nformat binary_middle_endian 1.0\nend_header\n", "unknown PLY format 'binary_middle_endian'", 2},
      {"ply\nformat ascii 1.0\n" + v3, "no end_header", 7},
      {"ply\n" + v3 + "end_header\n", "no format line", 7},
      {"ply\nformat ascii 1.0\nproperty float x\nend_header\n", "a property before any element", 3},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "unknown property type 'quad'", 4},
      {"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n1\n", "no x, y and z", 5},
      {"ply\nformat ascii 1.0\nwhatever\nend_header\n", "unknown header line 'whatever'", 3},
      {"ply\nformat ascii 1.0\n" + f1 + v3 + "end_header\n3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n", "face element comes before",
       10},
      {"ply\nformat ascii 1.0\n" + v3 +
           "element face 1\nproperty list uchar int corners\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "no vertex_indices list", 9},
      {"ply\nformat ascii 1.0\n" + v3 + f1 + "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "face 0 refers to vertex 3",
       13},
      {"ply\nformat ascii 1.0\n" + v3 + f1 + "end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "face 0 has 2 corners", 13},
      {"ply\nformat ascii 1.0\n" + v3 + f1 + "end_header\n0 0 0\n1 0 0\n0 1 0\n-1 0 1\n", "a bad list length", 13},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    const ParseError e = error_of(c.text, MeshFormat::ply, "bad.ply");
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), c.line) << e.what();
  }
  // Binary: the byte offset of the problem.
  std::string trunc = binary_ply(false);
  trunc.resize(trunc.size() - 3);
  const ParseError e = error_of(trunc, MeshFormat::ply, "bad.ply");
  EXPECT_FALSE(e.line().has_value());
  ASSERT_TRUE(e.byte_offset().has_value());
  EXPECT_EQ(*e.byte_offset(), trunc.size() - 13) << e.what();  // after the face's count of 4 (16 bytes needed)
  EXPECT_NE(std::string(e.what()).find("a list claims 4 items, more than the file holds"), std::string::npos)
      << e.what();
}

// ---------------------------------------------------------------------------
// STL

std::string facet(Vec3 a, Vec3 b, Vec3 c) {
  auto v = [](Vec3 p) {
    return "    vertex " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  };
  return "  facet normal 0 0 1\n   outer loop\n" + v(a) + v(b) + v(c) + "   endloop\n  endfacet\n";
}

TEST(ReadStl, AsciiWithSeveralSolids) {
  const std::string s = "solid first\n" + facet({0, 0, 0}, {1, 0, 0}, {0, 1, 0}) + "endsolid first\n" +
                        "solid second\n" + facet({1, 0, 0}, {1, 1, 0}, {0, 1, 0}) +
                        facet({5, 5, 5}, {6, 5, 5}, {5, 6, 5}) + "endsolid second\n";
  const ReadResult r = stl(s);
  EXPECT_EQ(r.mesh.num_faces(), 3u);
  EXPECT_EQ(r.mesh.num_vertices(), 7u);  // two corners shared between the solids
  EXPECT_EQ(r.mesh.faces[1], (Tri{1, 3, 2}));
  EXPECT_TRUE(r.warnings.empty());
}

TEST(ReadStl, AsciiPolygonFacetsAreSplit) {
  const std::string s =
      "solid q\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
      "vertex 0 1 0\nendloop\nendfacet\nendsolid q\n";
  const ReadResult r = stl(s);
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
  EXPECT_TRUE(has_warning(r, "1 polygons were split"));
}

std::string binary_stl(const Mesh& m, const std::string& header) {
  std::string s = header;
  s.resize(80, ' ');
  s += le(std::uint32_t(m.num_faces()));
  for (const Tri& t : m.faces) {
    s += le(0.f) + le(0.f) + le(0.f);
    for (Index v : t) s += le(float(m.positions[v].x)) + le(float(m.positions[v].y)) + le(float(m.positions[v].z));
    s += le(std::uint16_t(0));
  }
  return s;
}

TEST(ReadStl, BinaryWhoseHeaderStartsWithSolidIsReadAsBinary) {
  const Mesh box = test::box();
  const std::string s = binary_stl(box, "solid but actually binary, as SolidWorks writes them");
  ASSERT_TRUE(s.starts_with("solid"));
  const ReadResult r = stl(s);
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  EXPECT_EQ(r.mesh.num_vertices(), 8u);
  for (std::size_t f = 0; f < 12; ++f)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(r.mesh.positions[r.mesh.faces[f][k]], box.positions[box.faces[f][k]]);
}

TEST(ReadStl, WeldingIsOptional) {
  const std::string s = binary_stl(test::box(), "box");
  EXPECT_EQ(stl(s).mesh.num_vertices(), 8u);
  ReadOptions o;
  o.weld_stl = false;
  const ReadResult r = stl(s, o);
  EXPECT_EQ(r.mesh.num_vertices(), 36u);
  EXPECT_EQ(r.mesh.num_faces(), 12u);
  EXPECT_EQ(r.mesh.faces[11], (Tri{33, 34, 35}));
  // Ascii too.
  const std::string a = write_mesh_bytes(test::box(), MeshFormat::stl, WriteOptions{.binary = false});
  EXPECT_EQ(stl(a).mesh.num_vertices(), 8u);
  EXPECT_EQ(stl(a, o).mesh.num_vertices(), 36u);
}

TEST(ReadStl, PlusAndMinusZeroWeld) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0, 0, -0.0}, {0, -1, 0}};
  m.faces = {{0, 1, 2}, {3, 4, 1}};
  const ReadResult r = stl(binary_stl(m, "zeros"));
  EXPECT_EQ(r.mesh.num_vertices(), 4u);
  EXPECT_EQ(r.mesh.faces[1], (Tri{0, 3, 1}));
}

TEST(ReadStl, Errors) {
  // Ascii: the line of the problem.
  const ParseError a =
      error_of("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\n",
               MeshFormat::stl, "bad.stl");
  EXPECT_EQ(a.line(), 6u) << a.what();
  EXPECT_NE(std::string(a.what()).find("a facet has 2 vertices"), std::string::npos) << a.what();
  const ParseError b = error_of("solid x\nfacet normal 0 0 1\nbogus\n", MeshFormat::stl, "bad.stl");
  EXPECT_EQ(b.line(), 3u) << b.what();
  EXPECT_NE(std::string(b.what()).find("'bogus'"), std::string::npos) << b.what();
  const ParseError c = error_of("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n", MeshFormat::stl, "bad.stl");
  EXPECT_NE(std::string(c.what()).find("ends inside a facet"), std::string::npos) << c.what();
  const ParseError d = error_of("hello\n", MeshFormat::stl, "bad.stl");
  EXPECT_NE(std::string(d.what()).find("not an STL file"), std::string::npos) << d.what();
  // Binary: the size does not match the count at byte 80.
  std::string s = binary_stl(test::box(), "box");
  s += "xx";
  const ParseError e = error_of(s, MeshFormat::stl, "bad.stl");
  EXPECT_EQ(e.byte_offset(), 80u) << e.what();
  EXPECT_NE(std::string(e.what()).find("claims 12 triangles (684 bytes) but the file has 686 bytes"), std::string::npos)
      << e.what();
}

// ---------------------------------------------------------------------------
// glTF

// A GLB of a JSON document and a BIN chunk.
std::string glb(const std::string& json, const std::string& bin) {
  std::string j = json;
  while (j.size() % 4) j += ' ';
  std::string b = bin;
  while (b.size() % 4) b += '\0';
  std::string s = "glTF" + le(std::uint32_t(2)) + le(std::uint32_t(12 + 8 + j.size() + (b.empty() ? 0 : 8 + b.size())));
  s += le(std::uint32_t(j.size())) + "JSON" + j;
  if (!b.empty()) s += le(std::uint32_t(b.size())) + std::string("BIN\0", 4) + b;
  return s;
}
std::string floats(std::initializer_list<float> v) {
  std::string s;
  for (float x : v) s += le(x);
  return s;
}
std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const std::uint32_t n = std::uint8_t(in[i]) << 16 | std::uint8_t(in[i + 1]) << 8 | std::uint8_t(in[i + 2]);
    out += {k[n >> 18], k[(n >> 12) & 63], k[(n >> 6) & 63], k[n & 63]};
  }
  if (in.size() - i == 1) {
    const std::uint32_t n = std::uint8_t(in[i]) << 16;
    out += {k[n >> 18], k[(n >> 12) & 63], '=', '='};
  } else if (in.size() - i == 2) {
    const std::uint32_t n = std::uint8_t(in[i]) << 16 | std::uint8_t(in[i + 1]) << 8;
    out += {k[n >> 18], k[(n >> 12) & 63], k[(n >> 6) & 63], '='};
  }
  return out;
}

// One triangle (positions, uint16 indices 0 1 2) in buffer 0; `nodes` and `extra` are spliced in.
const std::string kTriBin = floats({0, 0, 0, 1, 0, 0, 0, 1, 0}) + le(std::uint16_t(0)) + le(std::uint16_t(1)) +
                            le(std::uint16_t(2)) + le(std::uint16_t(0));
std::string tri_json(const std::string& nodes, const std::string& scene_nodes = "[0]", const std::string& buffer = "") {
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":)" + scene_nodes + R"(}],"nodes":)" + nodes +
         R"(,"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
         R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],)"
         R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],)"
         R"("buffers":[{"byteLength":44)" +
         buffer + "}]}";
}

TEST(ReadGltf, MinimalGlb) {
  const ReadResult r = read(glb(tri_json(R"([{"mesh":0}])"), kTriBin), MeshFormat::glb, "t.glb");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}}));
}

TEST(ReadGltf, TextGltfWithAnEmbeddedBuffer) {
  const std::string json =
      tri_json(R"([{"mesh":0}])", "[0]", R"(,"uri":"data:application/octet-stream;base64,)" + base64(kTriBin) + "\"");
  const ReadResult r = read(json, MeshFormat::gltf, "t.gltf");
  EXPECT_EQ(r.mesh.positions, kTri);
  EXPECT_EQ(r.mesh.num_faces(), 1u);
}

TEST(ReadGltf, ExternalFilesAreNeverRead) {
  // A buffer naming a file: without a companion the reader gives, nothing is opened.
  const auto d = test::temp_dir("readers_gltf");
  test::write_text(d / "secret.bin", kTriBin);
  for (const auto& [uri, why] :
       std::vector<std::pair<std::string, std::string>>{{(d / "secret.bin").string(), "is an absolute path"},
                                                        {"secret.bin", "'secret.bin' it names is missing"},
                                                        {"file:///etc/passwd", "scheme 'file:'"}}) {
    SCOPED_TRACE(uri);
    const std::string json = tri_json(R"([{"mesh":0}])", "[0]", R"(,"uri":")" + uri + "\"");
    for (MeshFormat f : {MeshFormat::glb, MeshFormat::gltf}) {
      const ParseError e = error_of(f == MeshFormat::glb ? glb(json, "") : json, f, "t.gl");
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  }
}

const std::string kQuadBin = test::gltf_quad_bin();

// Companion files by path, recording what the reader asked for.
struct Companions {
  std::map<std::string, std::string> files;
  std::vector<std::string> asked;
  ReadOptions options() {
    ReadOptions o;
    o.companion = [this](const std::string& path) -> std::optional<std::string_view> {
      asked.push_back(path);
      const auto it = files.find(path);
      if (it == files.end()) return std::nullopt;
      return std::string_view(it->second);
    };
    return o;
  }
};

std::string gltf_error(const std::string& json, const ReadOptions& o) {
  try {
    read(json, MeshFormat::gltf, "model.gltf", o);
    ADD_FAILURE() << "no error";
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(ReadGltf, ExternalBufferFromACompanionFile) {
  Companions c;
  c.files["model.bin"] = kQuadBin;
  const ReadResult r = read(test::gltf_quad("model.bin"), MeshFormat::gltf, "model.gltf", c.options());
  EXPECT_EQ(c.asked, std::vector<std::string>{"model.bin"});
  EXPECT_EQ(r.mesh.num_vertices(), 4u);
  EXPECT_EQ(r.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
  // The same glTF with the buffer embedded reads alone.
  ASSERT_FALSE(r.self_contained.empty());
  EXPECT_EQ(r.self_contained.find("model.bin"), std::string::npos);
  const ReadResult alone = read(r.self_contained, MeshFormat::gltf, "model.gltf");
  EXPECT_EQ(alone.mesh.positions, r.mesh.positions);
  EXPECT_EQ(alone.mesh.faces, r.mesh.faces);
  // Embedded buffers alone need nothing stored again.
  EXPECT_TRUE(alone.self_contained.empty());
}

TEST(ReadGltf, CompanionPathsArePercentDecodedAndRelative) {
  Companions c;
  c.files["my model.bin"] = kQuadBin;
  c.files["sub/x.bin"] = kQuadBin;
  EXPECT_EQ(read(test::gltf_quad("my%20model.bin"), MeshFormat::gltf, "m.gltf", c.options()).mesh.num_faces(), 2u);
  EXPECT_EQ(read(test::gltf_quad("./sub/x.bin"), MeshFormat::gltf, "m.gltf", c.options()).mesh.num_faces(), 2u);
  EXPECT_EQ(c.asked, (std::vector<std::string>{"my model.bin", "sub/x.bin"}));
}

TEST(ReadGltf, UrisLeavingTheBundleAreRefusedUnasked) {
  Companions c;
  c.files["x.bin"] = kQuadBin;
  for (const auto& [uri, why] :
       std::vector<std::pair<std::string, std::string>>{{"../x.bin", "leaves the .gltf's directory ('..')"},
                                                        {"sub/../../x.bin", "leaves the .gltf's directory ('..')"},
                                                        {"%2e%2e/x.bin", "leaves the .gltf's directory ('..')"},
                                                        {"/etc/passwd", "is an absolute path"},
                                                        {"file:///etc/passwd", "names the scheme 'file:'"},
                                                        {"file:x.bin", "names the scheme 'file:'"},
                                                        {"https://example.com/x.bin", "names the scheme 'https:'"},
                                                        {"C:/x.bin", "names the scheme 'C:'"}}) {
    SCOPED_TRACE(uri);
    const std::string e = gltf_error(test::gltf_quad(uri), c.options());
    EXPECT_NE(e.find("buffers[0]: the uri '" + uri + "' is refused: it " + why), std::string::npos) << e;
  }
  EXPECT_TRUE(c.asked.empty());
}

TEST(ReadGltf, AMissingBinIsNamed) {
  Companions c;
  const std::string e = gltf_error(test::gltf_quad("model.bin"), c.options());
  EXPECT_NE(e.find("the file 'model.bin' it names is missing: upload it together with the .gltf (zipped, or chosen "
                   "together in the viewer)"),
            std::string::npos)
      << e;
}

// A 1x1 PNG.
const std::string kPng =
    std::string("\x89PNG\r\n\x1a\n", 8) + std::string("\0\0\0\rIHDR\0\0\0\1\0\0\0\1\x08\x02\0\0\0", 21);

// Two primitives of the triangle with materials 0 and 1 (the second with
// normals too, or the attributes given), material 0 textured (textures[0],
// by default the image) by an image in the BIN chunk.
std::string two_material_glb(const std::string& image_json, const std::string& image_bytes,
                             const std::string& second_attributes = R"({"POSITION":0,"NORMAL":0,"TEXCOORD_0":2})",
                             const std::string& texture_json = R"({"source":0})") {
  const std::string json =
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0,"TEXCOORD_0":2},"indices":1,"material":0},)"
      R"({"attributes":)" +
      second_attributes +
      R"(,"indices":1,"material":1}]}],)"
      R"("materials":[{"name":"red","pbrMetallicRoughness":{"baseColorFactor":[1,0,0,1],)"
      R"("baseColorTexture":{"index":0}}},{"name":"blue","pbrMetallicRoughness":{"baseColorFactor":[0,0,1,1]}}],)"
      R"("textures":[)" +
      texture_json + R"(],"images":[)" + image_json +
      R"(],"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"},)"
      R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"},)"
      R"({"bufferView":0,"componentType":5126,"count":3,"type":"VEC2"}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6},)"
      R"({"buffer":0,"byteOffset":44,"byteLength":)" +
      std::to_string(image_bytes.size()) + R"(}],"buffers":[{"byteLength":)" + std::to_string(44 + image_bytes.size()) +
      "}]}";
  return glb(json, kTriBin + image_bytes);
}

TEST(ReadGltf, MaterialsBecomeFaceMaterialsAcrossAttributeSets) {
  const ReadResult r =
      read(two_material_glb(R"({"bufferView":2,"mimeType":"image/png"})", kPng), MeshFormat::glb, "m.glb");
  ASSERT_EQ(r.mesh.num_faces(), 2u);
  EXPECT_EQ(r.face_material, (std::vector<std::uint32_t>{0, 1}));
  ASSERT_EQ(r.materials.size(), 2u);
  EXPECT_EQ(r.materials[0].name, "red");
  EXPECT_EQ(r.materials[0].kd, (std::array<float, 3>{1, 0, 0}));
  EXPECT_EQ(r.materials[1].name, "blue");
  EXPECT_EQ(r.materials[1].kd, (std::array<float, 3>{0, 0, 1}));
  EXPECT_FALSE(r.materials[1].texture);
  // The embedded image is the red material's texture.
  ASSERT_EQ(r.textures.size(), 1u);
  EXPECT_EQ(r.materials[0].texture, 0u);
  EXPECT_EQ(r.textures[0].bytes, kPng);
  EXPECT_EQ(r.textures[0].name, "image0.png");
  EXPECT_TRUE(r.mesh.has_uvs());
  EXPECT_TRUE(has_warning(r, "normals dropped")) << ::testing::PrintToString(r.warnings);
  EXPECT_TRUE(r.self_contained.empty());
}

// A textured primitive beside one with no texture coordinates (nor normals):
// the texture keeps its coordinates, the other's faces take (0, 0) and keep
// their colour.
TEST(ReadGltf, ATexturedPrimitiveKeepsItsUvsBesideOneWithout) {
  const ReadResult r = read(two_material_glb(R"({"bufferView":2,"mimeType":"image/png"})", kPng, R"({"POSITION":0})"),
                            MeshFormat::glb, "m.glb");
  ASSERT_EQ(r.mesh.num_vertices(), 6u);
  ASSERT_TRUE(r.mesh.has_uvs()) << ::testing::PrintToString(r.warnings);
  // The positions' floats read as VEC2: (0, 0), (0, 1), (0, 0), v flipped.
  EXPECT_EQ(r.mesh.uvs[0], (Vec2f{0, 1}));
  EXPECT_EQ(r.mesh.uvs[2], (Vec2f{0, 1}));
  for (std::size_t v = 3; v < 6; ++v) EXPECT_EQ(r.mesh.uvs[v], (Vec2f{0, 0}));
  EXPECT_EQ(r.warnings, std::vector<std::string>{}) << ::testing::PrintToString(r.warnings);
  EXPECT_EQ(r.face_material, (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(r.materials[0].texture, 0u);
  EXPECT_EQ(r.materials[1].kd, (std::array<float, 3>{0, 0, 1}));

  // The untextured primitive with coordinates, the textured one without: dropped, as before.
  const std::string swapped = [] {
    std::string g = two_material_glb(R"({"bufferView":2,"mimeType":"image/png"})", kPng, R"({"POSITION":0})");
    const std::string a = R"("material":0})", b = R"("material":1})";
    g.replace(g.find(a), a.size(), R"("material":9})");
    g.replace(g.find(b), b.size(), a);
    g.replace(g.find(R"("material":9})"), a.size(), b);
    return g;
  }();
  const ReadResult s = read(swapped, MeshFormat::glb, "m.glb");
  EXPECT_EQ(s.face_material, (std::vector<std::uint32_t>{0, 1}));
  EXPECT_EQ(s.materials[0].name, "blue");
  EXPECT_FALSE(s.mesh.has_uvs());
  EXPECT_TRUE(has_warning(s, "texture coordinates dropped")) << ::testing::PrintToString(s.warnings);

  // Both primitives textured, one without coordinates: kept, and said.
  std::string shared = two_material_glb(R"({"bufferView":2,"mimeType":"image/png"})", kPng, R"({"POSITION":0})");
  shared.replace(shared.find(R"("material":1})"), 13, R"("material":0})");
  const ReadResult both = read(shared, MeshFormat::glb, "m.glb");
  EXPECT_TRUE(both.mesh.has_uvs());
  EXPECT_TRUE(has_warning(both, "texture coordinates missing on 1 textured primitive(s)"))
      << ::testing::PrintToString(both.warnings);
}

// The image as a data: URI shows as the embedded one does.
TEST(ReadGltf, TextureFromADataUri) {
  const ReadResult r = read(two_material_glb(R"({"uri":"data:image/png;base64,)" + base64(kPng) + R"("})", ""),
                            MeshFormat::glb, "m.glb");
  ASSERT_EQ(r.textures.size(), 1u) << ::testing::PrintToString(r.warnings);
  EXPECT_EQ(r.textures[0].bytes, kPng);
  EXPECT_EQ(r.textures[0].name, "image0.png");
  EXPECT_EQ(r.materials[0].texture, 0u);
  EXPECT_TRUE(r.self_contained.empty());
}

TEST(ReadGltf, UnusableImagesAreWarnings) {
  // A texture whose only image is KTX2 (KHR_texture_basisu): said, not silent.
  const ReadResult ktx2 =
      read(two_material_glb(R"({"bufferView":2,"mimeType":"image/ktx2"})", kPng, R"({"POSITION":0,"TEXCOORD_0":2})",
                            R"({"extensions":{"KHR_texture_basisu":{"source":0}}})"),
           MeshFormat::glb, "m.glb");
  EXPECT_TRUE(ktx2.textures.empty());
  EXPECT_TRUE(has_warning(ktx2,
                          "the texture of the material 'red' (textures[0]) has no PNG or JPEG image, only an "
                          "image of KHR_texture_basisu (KTX2 and WebP are not shown)"))
      << ::testing::PrintToString(ktx2.warnings);
  EXPECT_EQ(ktx2.materials[0].kd, (std::array<float, 3>{1, 0, 0}));
  // A WebP in the buffer, a missing file, an image only KTX2 gives.
  const ReadResult webp =
      read(two_material_glb(R"({"bufferView":2,"mimeType":"image/webp"})", std::string("RIFF\0\0\0\0WEBP", 12)),
           MeshFormat::glb, "m.glb");
  EXPECT_TRUE(webp.textures.empty());
  EXPECT_TRUE(has_warning(webp, "the texture 'image0' of the material 'red' is an image/webp image, not PNG or JPEG"))
      << ::testing::PrintToString(webp.warnings);
  const ReadResult missing = read(two_material_glb(R"({"uri":"tex.png"})", ""), MeshFormat::glb, "m.glb");
  EXPECT_TRUE(missing.textures.empty());
  EXPECT_TRUE(has_warning(missing,
                          "the texture 'tex.png' of the material 'red' is not shown: the file 'tex.png' it "
                          "names is missing: upload it together with the .gltf"))
      << ::testing::PrintToString(missing.warnings);
  EXPECT_EQ(missing.materials.size(), 2u);
  // The PNG beside it, as a companion: read, and embedded in the self-contained copy.
  Companions c;
  c.files["tex.png"] = kPng;
  const ReadResult found = read(two_material_glb(R"({"uri":"tex.png"})", ""), MeshFormat::glb, "m.glb", c.options());
  ASSERT_EQ(found.textures.size(), 1u);
  EXPECT_EQ(found.textures[0].name, "tex.png");
  ASSERT_FALSE(found.self_contained.empty());
  const ReadResult alone = read(found.self_contained, MeshFormat::glb, "m.glb");
  ASSERT_EQ(alone.textures.size(), 1u);
  EXPECT_EQ(alone.textures[0].bytes, kPng);
}

TEST(ReadGltf, NodeTransformsAndHierarchy) {
  // Node 0 translates by (10, 0, 0) and holds node 1, which scales by 2 and shows the mesh.
  const ReadResult r =
      read(glb(tri_json(R"([{"translation":[10,0,0],"children":[1]},{"scale":[2,2,2],"mesh":0}])"), kTriBin),
           MeshFormat::glb, "t.glb");
  const std::vector<Vec3> want = {{10, 0, 0}, {12, 0, 0}, {10, 2, 0}};
  EXPECT_EQ(r.mesh.positions, want);
  // A column-major matrix; a 90-degree rotation about z (quaternion x y z w).
  const ReadResult m = read(glb(tri_json(R"([{"matrix":[1,0,0,0, 0,1,0,0, 0,0,1,0, 5,6,7,1],"mesh":0}])"), kTriBin),
                            MeshFormat::glb, "t.glb");
  EXPECT_EQ(m.mesh.positions[1], (Vec3{6, 6, 7}));
  const double h = std::sqrt(0.5);
  const ReadResult q = read(
      glb(tri_json(R"([{"rotation":[0,0,)" + std::to_string(h) + "," + std::to_string(h) + R"(],"mesh":0}])"), kTriBin),
      MeshFormat::glb, "t.glb");
  EXPECT_NEAR(q.mesh.positions[1].x, 0, 1e-6);
  EXPECT_NEAR(q.mesh.positions[1].y, 1, 1e-6);
  // A mirroring scale reverses the winding so that the faces still face out.
  const ReadResult mirror = read(glb(tri_json(R"([{"scale":[-1,1,1],"mesh":0}])"), kTriBin), MeshFormat::glb, "t.glb");
  EXPECT_EQ(mirror.mesh.faces, (std::vector<Tri>{{0, 2, 1}}));
  // Two nodes showing one mesh: instanced twice.
  const ReadResult two = read(glb(tri_json(R"([{"mesh":0},{"mesh":0,"translation":[0,0,1]}])", "[0,1]"), kTriBin),
                              MeshFormat::glb, "t.glb");
  EXPECT_EQ(two.mesh.num_vertices(), 6u);
  EXPECT_EQ(two.mesh.faces, (std::vector<Tri>{{0, 1, 2}, {3, 4, 5}}));
  EXPECT_EQ(two.mesh.positions[5], (Vec3{0, 1, 1}));
}

TEST(ReadGltf, StripsAndFansAndSkippedPoints) {
  const std::string bin = floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0});
  auto doc = [&](int mode) {
    return R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":)" +
           std::to_string(mode) +
           R"(}]}],"accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"}],)"
           R"("bufferViews":[{"buffer":0,"byteLength":48}],"buffers":[{"byteLength":48}]})";
  };
  EXPECT_EQ(read(glb(doc(5), bin), MeshFormat::glb, "s.glb").mesh.faces, (std::vector<Tri>{{0, 1, 2}, {2, 1, 3}}));
  EXPECT_EQ(read(glb(doc(6), bin), MeshFormat::glb, "f.glb").mesh.faces, (std::vector<Tri>{{0, 1, 2}, {0, 2, 3}}));
  const ParseError e = error_of(glb(doc(0), bin), MeshFormat::glb, "p.glb");
  EXPECT_NE(std::string(e.what()).find("no triangles"), std::string::npos) << e.what();
}

// Sparse accessors as the glTF 2.0 specification (3.6.2.3) defines them:
// without a bufferView the base is zeros; with one, its values; then each
// of `count` indices takes its value from the sparse values.
TEST(ReadGltf, SparseAccessorsSubstituteTheirElements) {
  // Indices (unsigned short) at byte 0, values (two VEC3) at byte 4, base at byte 28.
  const std::string idx = le(std::uint16_t(1)) + le(std::uint16_t(2));
  const std::string bin = idx + floats({1, 0, 0, 0, 1, 0}) + floats({5, 5, 5, 5, 5, 5, 5, 5, 5});
  auto doc = [](const std::string& base) {
    return R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
           R"("accessors":[{)" +
           base +
           R"("componentType":5126,"count":3,"type":"VEC3","sparse":{"count":2,)"
           R"("indices":{"bufferView":0,"componentType":5123},"values":{"bufferView":1}}}],)"
           R"("bufferViews":[{"buffer":0,"byteLength":4},{"buffer":0,"byteOffset":4,"byteLength":24},)"
           R"({"buffer":0,"byteOffset":28,"byteLength":36}],"buffers":[{"byteLength":64}]})";
  };
  const Mesh zeros = read(glb(doc(""), bin), MeshFormat::glb, "z.glb").mesh;
  EXPECT_EQ(zeros.positions, (std::vector<Vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
  EXPECT_EQ(zeros.faces, (std::vector<Tri>{{0, 1, 2}}));
  const Mesh based = read(glb(doc(R"("bufferView":2,)"), bin), MeshFormat::glb, "b.glb").mesh;
  EXPECT_EQ(based.positions, (std::vector<Vec3>{{5, 5, 5}, {1, 0, 0}, {0, 1, 0}}));
  // Indices out of order, or past the elements: refused, naming the index.
  const std::string back = le(std::uint16_t(2)) + le(std::uint16_t(1)) + bin.substr(4);
  EXPECT_NE(
      std::string(error_of(glb(doc(""), back), MeshFormat::glb, "o.glb").what()).find("not after the one before it"),
      std::string::npos);
  const std::string past = le(std::uint16_t(1)) + le(std::uint16_t(3)) + bin.substr(4);
  EXPECT_NE(std::string(error_of(glb(doc(""), past), MeshFormat::glb, "p.glb").what()).find("past the 3 elements"),
            std::string::npos);
}

// glTF 1.0 (objects by name where 2.0 has arrays): said as such, not as a
// malformed 2.0 file.
TEST(ReadGltf, Gltf1IsRefusedByName) {
  for (const std::string& doc : {std::string(R"({"asset":{"version":"1.0"},"buffers":{"b":{"uri":"data:,"}}})"),
                                 std::string(R"({"buffers":{"b":{"uri":"data:,"}},"meshes":{}})")}) {
    const ParseError e = error_of(doc, MeshFormat::gltf, "old.gltf");
    EXPECT_NE(std::string(e.what()).find("glTF 1.0 is not supported (only glTF 2.0)"), std::string::npos) << e.what();
  }
}

TEST(ReadGltf, DracoCompressedPrimitive) {
  // A KHR_draco_mesh_compression primitive whose bufferView holds our own .drc bytes.
  Mesh m = test::uv_sphere(1.0, 6, 8);
  const std::string drc = write_mesh_bytes(m, MeshFormat::drc);
  const std::string json =
      R"({"asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],)"
      R"("extensionsRequired":["KHR_draco_mesh_compression"],"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1,"extensions":{"KHR_draco_mesh_compression":)"
      R"({"bufferView":0,"attributes":{"POSITION":0}}}}]}],)"
      R"("accessors":[{"componentType":5126,"count":)" +
      std::to_string(m.num_vertices()) + R"(,"type":"VEC3"},{"componentType":5125,"count":)" +
      std::to_string(3 * m.num_faces()) + R"(,"type":"SCALAR"}],"bufferViews":[{"buffer":0,"byteLength":)" +
      std::to_string(drc.size()) + R"(}],"buffers":[{"byteLength":)" + std::to_string(drc.size()) + "}]}";
  const ReadResult r = read(glb(json, drc), MeshFormat::glb, "d.glb");
  EXPECT_EQ(r.mesh.num_faces(), m.num_faces());
  EXPECT_EQ(r.mesh.num_vertices(), m.num_vertices());
  EXPECT_NEAR(bounding_box(r.mesh).diagonal(), bounding_box(m).diagonal(), 1e-3);
  // A Draco attribute id that does not exist is an error, not a crash.
  std::string bad = json;
  const std::string ids = R"("attributes":{"POSITION":0}})";
  bad.replace(bad.find(ids), ids.size(), R"("attributes":{"POSITION":9}})");
  const ParseError e = error_of(glb(bad, drc), MeshFormat::glb, "d.glb");
  EXPECT_NE(std::string(e.what()).find("no attribute 9"), std::string::npos) << e.what();
}

TEST(ReadGltf, HostileStructuresAreRefused) {
  struct Case {
    std::string json, says;
  };
  const std::string ok_nodes = R"([{"mesh":0}])";
  const std::vector<Case> cases = {
      {tri_json(R"([{"mesh":3}])"), "nodes[0].mesh refers to mesh 3, but there are 1"},
      {tri_json(ok_nodes, "[7]"), "scenes[0].nodes[0] refers to node 7, but there are 1"},
      {tri_json(R"([{"children":[1]},{"children":[0],"mesh":0}])"), "reached twice"},
      {tri_json(R"([{"children":[2]},{"children":[2]},{"mesh":0}])", "[0,1]"), "child of more than one node"},
      {tri_json(R"([{"mesh":0}])", "[0,0]"), "reached twice"},
      {tri_json(R"([{"mesh":-1}])"), "refers to mesh -1"},
      {tri_json(R"([{"mesh":"zero"}])"), "refers to mesh \"zero\""},
      {tri_json(R"([{"mesh":0,"matrix":[1,2,3]}])"), "matrix is not an array of 16 numbers"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":1000000000000,"type":"VEC3"}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":44}]})",
       "1000000000000 elements of 12 bytes from byte 0 do not fit in its bufferView of 36 bytes"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
       R"("bufferViews":[{"buffer":0,"byteOffset":40,"byteLength":36}],"buffers":[{"byteLength":44}]})",
       "bufferViews[0] covers bytes 40..76 of a buffer of 44"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":4000}]})",
       "fewer than its byteLength 4000"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":0}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3"}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":44}]})",
       "indices must be unsigned"},
      {tri_json(ok_nodes).replace(tri_json(ok_nodes).find("\"VEC3\""), 6, "\"VEC2\""),
       "has type \"VEC2\", expected VEC3"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":2,"type":"VEC3"},)"
       R"({"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":24},{"buffer":0,"byteOffset":36,"byteLength":6}],)"
       R"("buffers":[{"byteLength":44}]})",
       "index 2 is 2, but there are 2 vertices"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","sparse":{}}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":44}]})",
       "sparse has no count"},
      {R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
       R"("accessors":[{"bufferView":0,"componentType":5130,"count":3,"type":"VEC3"}],)"
       R"("bufferViews":[{"buffer":0,"byteLength":36}],"buffers":[{"byteLength":44}]})",
       "unknown componentType 5130"},
      {R"([1, 2, 3])", "not an object"},
      {R"({"asset":)", "the JSON chunk is malformed"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.json);
    const ParseError e = error_of(glb(c.json, kTriBin), MeshFormat::glb, "hostile.glb");
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    EXPECT_EQ(e.file(), "hostile.glb");
  }
  // An instancing bomb: 40000 nodes showing one mesh of 1000 triangles (a 36 KB buffer).
  std::string nodes = "[", roots = "[";
  for (int i = 0; i < 40000; ++i) {
    nodes += std::string(i ? "," : "") + R"({"mesh":0})";
    roots += std::string(i ? "," : "") + std::to_string(i);
  }
  const std::string bomb_json = R"({"asset":{"version":"2.0"},"scenes":[{"nodes":)" + roots + R"(]}],"nodes":)" +
                                nodes +
                                R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],)"
                                R"("accessors":[{"bufferView":0,"componentType":5126,"count":3000,"type":"VEC3"}],)"
                                R"("bufferViews":[{"buffer":0,"byteLength":36000}],"buffers":[{"byteLength":36000}]})";
  const ParseError bomb = error_of(glb(bomb_json, std::string(36000, '\0')), MeshFormat::glb, "bomb.glb");
  EXPECT_NE(std::string(bomb.what()).find("instantiates its meshes into over"), std::string::npos) << bomb.what();
  // JSON nested a million deep: refused, without exhausting the stack.
  const ParseError deep =
      error_of(glb(std::string(1000000, '[') + std::string(1000000, ']'), ""), MeshFormat::glb, "deep.glb");
  EXPECT_NE(std::string(deep.what()).find("the JSON nests arrays and objects 1000000 deep"), std::string::npos)
      << deep.what();
  // Malformed JSON in a text .gltf: the line.
  const ParseError text =
      error_of("{\n\"asset\": {\n\"version\": \"2.0\"\n},\n\"meshes\": [ oops ]\n}\n", MeshFormat::gltf, "t.gltf");
  EXPECT_EQ(text.line(), 5u) << text.what();
  // The GLB container: version, length, chunk type.
  std::string g = glb(tri_json(ok_nodes), kTriBin);
  std::string v1 = g;
  v1[4] = 1;
  EXPECT_EQ(error_of(v1, MeshFormat::glb, "v.glb").byte_offset(), 4u);
  EXPECT_EQ(error_of(g.substr(0, g.size() - 8), MeshFormat::glb, "v.glb").byte_offset(), 8u);
  std::string chunk = g;
  chunk[16] = 'X';
  EXPECT_EQ(error_of(chunk, MeshFormat::glb, "v.glb").byte_offset(), 16u);
}

// ---------------------------------------------------------------------------
// format_from_name

TEST(FormatFromName, ExtensionsInAnyCase) {
  EXPECT_EQ(format_from_name("a.off"), MeshFormat::off);
  EXPECT_EQ(format_from_name("A.OFF"), MeshFormat::off);
  EXPECT_EQ(format_from_name("dir/b.Ply"), MeshFormat::ply);
  EXPECT_EQ(format_from_name("/x.y/z.ObJ"), MeshFormat::obj);
  EXPECT_EQ(format_from_name("c:\\meshes\\m.STL"), MeshFormat::stl);
  EXPECT_EQ(format_from_name("m.drc"), MeshFormat::drc);
  EXPECT_EQ(format_from_name("m.GLB"), MeshFormat::glb);
  EXPECT_EQ(format_from_name("m.gltf"), MeshFormat::gltf);
  EXPECT_EQ(format_from_name("archive.tar.ply"), MeshFormat::ply);
  // Bare names.
  EXPECT_EQ(format_from_name("ply"), MeshFormat::ply);
  EXPECT_EQ(format_from_name("STL"), MeshFormat::stl);
  for (MeshFormat f : {MeshFormat::off, MeshFormat::obj, MeshFormat::ply, MeshFormat::stl, MeshFormat::drc,
                       MeshFormat::glb, MeshFormat::gltf, MeshFormat::xyz, MeshFormat::pts}) {
    EXPECT_EQ(format_from_name(to_string(f)), f);
    EXPECT_EQ(format_from_name(std::string("x.") + to_string(f)), f);
    EXPECT_TRUE(can_read(f));
    EXPECT_EQ(can_write(f), f != MeshFormat::gltf && f != MeshFormat::pts);
  }
  EXPECT_EQ(writable_formats(), "off, obj, ply, stl, drc, glb, xyz");
  EXPECT_EQ(readable_formats(), "off, obj, ply, stl, drc, glb, gltf, xyz, pts");
}

TEST(FormatFromName, Errors) {
  struct Case {
    std::string name, says;
  };
  const std::vector<Case> cases = {
      {"", "no extension"},
      {"dir.v2/mesh", "no extension"},
      {"mesh.tar.gz", "unknown mesh format '.gz' of 'mesh.tar.gz'"},
      {"mesh.", "unknown mesh format '.'"},
      {"model.3DS", "unknown mesh format '.3ds'"},
      {"las", "unknown mesh format '.las'"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    try {
      format_from_name(c.name);
      ADD_FAILURE() << "no exception";
    } catch (const UnsupportedFormat& e) {
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("off, obj, ply, stl, drc, glb, gltf, xyz, pts"), std::string::npos)
          << e.what();
    }
  }
  // UnsupportedFormat is an InvalidInput (a server answers 400).
  EXPECT_THROW(format_from_name("a.b"), InvalidInput);
}

}  // namespace
}  // namespace cgview
