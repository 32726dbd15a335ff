// Round trips through every writable format, each file checked by a reader
// that is not ours: CGAL's (OFF, OBJ, PLY, STL), Draco's own draco_decoder
// (.drc) and assimp (.glb); then our reader reads everything back.  Point
// clouds (meshes with no faces) through PLY, XYZ and Draco, read back by
// Open3D and draco_decoder.  CGAL's
// headers are included here only (the test links cgview_cgal).
#include <gtest/gtest.h>

#include <CGAL/IO/Color.h>
#include <CGAL/IO/OBJ.h>
#include <CGAL/IO/OFF.h>
#include <CGAL/IO/PLY.h>
#include <CGAL/IO/STL.h>
#include <CGAL/IO/polygon_soup_io.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/mesh.h"
#include "core/mesh_report.h"
#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "format_variants.h"
#include "open3d_reference.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;

using test::Variant;
using test::variants;

const fs::path& dir() {
  static const fs::path d = test::temp_dir("round_trip");
  return d;
}

fs::path write(const Mesh& m, const std::string& tag, const Variant& v) {
  const fs::path p = dir() / (tag + "_" + v.label + "." + v.ext);
  WriteOptions o;
  o.binary = v.binary;
  write_mesh(m, p, o);
  EXPECT_TRUE(fs::exists(p));
  EXPECT_FALSE(fs::exists(p.string() + ".part"));
  return p;
}

// What float storage makes of a coordinate.
Vec3 as_float(Vec3 p) { return to_double(to_float(p)); }

// The worst Draco quantization error for a mesh, with a factor 2 of margin.
double draco_tolerance(const Mesh& m, int bits = 14) { return bounding_box(m).diagonal() / double(1 << bits) * 2; }

// Maps each point to an original vertex within `tol` (brute force over a
// small grid of cells); -1 where none is near.
std::vector<long> match_points(const std::vector<Vec3>& points, const Mesh& original, double tol) {
  std::map<std::array<long, 3>, std::vector<Index>> cells;
  const double cell = std::max(tol, 1e-12) * 4;
  auto key = [&](Vec3 p) {
    return std::array<long, 3>{long(std::floor(p.x / cell)), long(std::floor(p.y / cell)),
                               long(std::floor(p.z / cell))};
  };
  for (Index v = 0; v < original.num_vertices(); ++v) cells[key(original.positions[v])].push_back(v);
  std::vector<long> out(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto k = key(points[i]);
    double best = tol;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({k[0] + dx, k[1] + dy, k[2] + dz});
          if (it == cells.end()) continue;
          for (Index v : it->second) {
            const double d = norm(original.positions[v] - points[i]);
            if (d <= best) {
              best = d;
              out[i] = long(v);
            }
          }
        }
  }
  return out;
}

// A triangle as a rotation-independent key (smallest index first, orientation kept).
std::array<long, 3> canonical(std::array<long, 3> t) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return t;
}

// Checks that (points, triangles) is the original mesh up to vertex order,
// within `tol`: every point near an original vertex, the same oriented faces.
void expect_same_geometry(const std::vector<Vec3>& points, const std::vector<std::array<long, 3>>& tris,
                          const Mesh& original, double tol, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(tris.size(), original.num_faces());
  const std::vector<long> to = match_points(points, original, tol);
  const long unmatched = long(std::count(to.begin(), to.end(), -1));
  EXPECT_EQ(unmatched, 0) << "points farther than " << tol << " from every original vertex";
  std::multiset<std::array<long, 3>> want, got;
  for (const Tri& t : original.faces) want.insert(canonical({long(t[0]), long(t[1]), long(t[2])}));
  for (const auto& t : tris)
    got.insert(canonical({to[std::size_t(t[0])], to[std::size_t(t[1])], to[std::size_t(t[2])]}));
  EXPECT_TRUE(want == got) << "the faces differ";
}

// CGAL's reading of a file as a polygon soup.
struct Soup {
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> polygons;
};
Soup cgal_soup(const fs::path& p) {
  Soup s;
  EXPECT_TRUE(CGAL::IO::read_polygon_soup(p.string(), s.points, s.polygons, CGAL::parameters::verbose(false)))
      << "CGAL cannot read " << p;
  return s;
}
Vec3 vec(const Point3& p) { return {p.x(), p.y(), p.z()}; }

// CGAL's soup equals the mesh in order: same points (to `tol`), same polygons.
void expect_soup_equals(const Soup& s, const Mesh& m, double rel_tol, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_EQ(s.points.size(), m.num_vertices());
  ASSERT_EQ(s.polygons.size(), m.num_faces());
  double worst = 0;
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    const Vec3 d = vec(s.points[v]) - m.positions[v];
    const double scale =
        std::max({1.0, std::abs(m.positions[v].x), std::abs(m.positions[v].y), std::abs(m.positions[v].z)});
    worst = std::max(worst, norm(d) / scale);
  }
  EXPECT_LE(worst, rel_tol);
  std::size_t wrong = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const auto& poly = s.polygons[f];
    if (poly.size() != 3 || poly[0] != m.faces[f][0] || poly[1] != m.faces[f][1] || poly[2] != m.faces[f][2]) ++wrong;
  }
  EXPECT_EQ(wrong, 0u) << "polygons that differ from the faces";
}

constexpr double kFloatTol = 1.2e-7;  // float's relative precision (2^-23), with margin

struct Shape {
  std::string name;
  Mesh mesh;
};
const std::vector<Shape>& shapes() {
  static const std::vector<Shape> s = [] {
    std::vector<Shape> out = {{"box", test::box({-1, -2, -3}, {4, 5, 6})},
                              {"sphere", test::uv_sphere(1.5, 12, 24)},
                              {"torus", test::torus()},
                              {"grid", test::grid(5)}};
    out.push_back({"elephant", read_mesh(test::sample("elephant.off"))});
    out.push_back({"colored_tetra", read_mesh(test::sample("colored_tetra.ply"))});
    return out;
  }();
  return s;
}

bool have(const std::string& tool) { return test::run("command -v " + tool) == 0; }

// The number after a label in a tool's output ("Vertices:     2775"), or -1.
long count_after(const std::string& text, const std::string& label) {
  const auto at = text.find(label);
  if (at == std::string::npos) return -1;
  std::istringstream in(text.substr(at + label.size()));
  long n = -1;
  in >> n;
  return n;
}

// ---------------------------------------------------------------------------

// Our own reader reads back everything we write with the same counts and values.
TEST(RoundTrip, OwnReaderReadsBackEveryFormat) {
  for (const Shape& shape : shapes()) {
    const Mesh& m = shape.mesh;
    for (const Variant& v : variants()) {
      SCOPED_TRACE(shape.name + " as " + v.label);
      const fs::path p = write(m, shape.name, v);
      const ReadResult r = read_mesh_file(p);
      EXPECT_EQ(r.format, v.format);
      ASSERT_NO_THROW(r.mesh.validate());
      ASSERT_EQ(r.mesh.num_faces(), m.num_faces());
      ASSERT_EQ(r.mesh.num_vertices(), m.num_vertices());  // STL: after welding
      switch (v.format) {
        case MeshFormat::off:
        case MeshFormat::obj:  // shortest round-trip text: exact
          EXPECT_EQ(r.mesh.positions, m.positions);
          EXPECT_EQ(r.mesh.faces, m.faces);
          break;
        case MeshFormat::ply:
        case MeshFormat::glb: {  // float32, same order
          std::size_t off = 0;
          for (std::size_t i = 0; i < m.num_vertices(); ++i) off += r.mesh.positions[i] != as_float(m.positions[i]);
          EXPECT_EQ(off, 0u) << "positions that are not the float rounding of the original";
          EXPECT_EQ(r.mesh.faces, m.faces);
          break;
        }
        case MeshFormat::stl:
        case MeshFormat::drc: {  // STL: welded in corner order; Draco: reordered and quantized
          std::vector<std::array<long, 3>> tris;
          for (const Tri& t : r.mesh.faces) tris.push_back({long(t[0]), long(t[1]), long(t[2])});
          const double tol = v.format == MeshFormat::drc ? draco_tolerance(m) : 1e-6 * bounding_box(m).diagonal();
          expect_same_geometry(r.mesh.positions, tris, m, tol, "read back");
          break;
        }
        default:
          break;
      }
      // The report agrees with the original's (closedness, genus).
      const MeshReport a = mesh_report(m), b = mesh_report(r.mesh);
      EXPECT_EQ(b.closed, a.closed);
      EXPECT_EQ(b.genus, a.genus);
      EXPECT_EQ(b.boundary_loops, a.boundary_loops);
    }
  }
}

// CGAL's readers read our OFF, OBJ and PLY (both encodings): same counts, same
// order, coordinates within float precision (exact for the text formats).
TEST(RoundTrip, CgalReadsOurOffObjAndPly) {
  for (const Shape& shape : shapes()) {
    for (const Variant& v : variants()) {
      if (v.format != MeshFormat::off && v.format != MeshFormat::obj && v.format != MeshFormat::ply) continue;
      const fs::path p = write(shape.mesh, shape.name, v);
      const double tol = v.format == MeshFormat::ply ? kFloatTol : 1e-15;
      expect_soup_equals(cgal_soup(p), shape.mesh, tol, shape.name + " as " + v.label + " read by CGAL");
    }
  }
}

// CGAL reads our STL as a triangle soup (merging equal points): as many
// triangles, as many distinct points as the original has vertices.
TEST(RoundTrip, CgalReadsOurStl) {
  for (const Shape& shape : shapes()) {
    for (const char* label : {"stl_binary", "stl_ascii"}) {
      const Variant& v =
          *std::find_if(variants().begin(), variants().end(), [&](const Variant& x) { return x.label == label; });
      SCOPED_TRACE(shape.name + " as " + label);
      const fs::path p = write(shape.mesh, shape.name, v);
      std::vector<Point3> points;
      std::vector<std::array<std::size_t, 3>> triangles;
      ASSERT_TRUE(CGAL::IO::read_STL(p.string(), points, triangles, CGAL::parameters::verbose(false)));
      EXPECT_EQ(triangles.size(), shape.mesh.num_faces());
      EXPECT_EQ(points.size(), shape.mesh.num_vertices());
      std::vector<Vec3> pts;
      for (const Point3& q : points) pts.push_back(vec(q));
      std::vector<std::array<long, 3>> tris;
      for (const auto& t : triangles) tris.push_back({long(t[0]), long(t[1]), long(t[2])});
      expect_same_geometry(pts, tris, shape.mesh, 1e-6 * bounding_box(shape.mesh).diagonal(), "CGAL's soup");
      // And our welding gives back the original vertex count.
      EXPECT_EQ(read_mesh(p).num_vertices(), shape.mesh.num_vertices());
    }
  }
}

// Draco's own command-line decoder reads our .drc; CGAL reads its output.
TEST(RoundTrip, DracoDecoderReadsOurDrc) {
  if (!have("draco_decoder")) FAIL() << "draco_decoder is missing (install Debian's 'draco')";
  const Variant& drc = variants()[6];
  for (const Shape& shape : shapes()) {
    SCOPED_TRACE(shape.name);
    const fs::path in = write(shape.mesh, shape.name, drc);
    for (const char* ext : {"ply", "obj"}) {
      const fs::path out = dir() / (shape.name + "_decoded." + ext);
      std::string log;
      ASSERT_EQ(test::run("draco_decoder -i '" + in.string() + "' -o '" + out.string() + "'", &log), 0) << log;
      const Soup s = cgal_soup(out);
      EXPECT_EQ(s.points.size(), shape.mesh.num_vertices()) << ext;
      std::vector<Vec3> pts;
      for (const Point3& q : s.points) pts.push_back(vec(q));
      std::vector<std::array<long, 3>> tris;
      for (const auto& poly : s.polygons) {
        ASSERT_EQ(poly.size(), 3u);
        tris.push_back({long(poly[0]), long(poly[1]), long(poly[2])});
      }
      expect_same_geometry(pts, tris, shape.mesh, draco_tolerance(shape.mesh), std::string("draco_decoder -> ") + ext);
    }
  }
  // Coarser quantization is honoured: 8 bits are within 8-bit error, not 14-bit.
  const Mesh sphere = test::uv_sphere(1.0, 12, 24);
  WriteOptions o;
  o.position_bits = 8;
  const fs::path p = dir() / "sphere8.drc";
  write_mesh(sphere, p, o);
  const Mesh r = read_mesh(p);
  std::vector<std::array<long, 3>> tris;
  for (const Tri& t : r.faces) tris.push_back({long(t[0]), long(t[1]), long(t[2])});
  expect_same_geometry(r.positions, tris, sphere, draco_tolerance(sphere, 8), "8-bit positions");
  double worst = 0;
  for (const Vec3& q : r.positions) {
    const std::vector<long> to = match_points({q}, sphere, draco_tolerance(sphere, 8));
    if (to[0] >= 0) worst = std::max(worst, norm(q - sphere.positions[std::size_t(to[0])]));
  }
  EXPECT_GT(worst, draco_tolerance(sphere, 14)) << "8-bit quantization should be visibly coarser";
}

// assimp reads our .glb: its counts, and its OBJ export read by CGAL.
TEST(RoundTrip, AssimpReadsOurGlb) {
  if (!have("assimp")) FAIL() << "assimp is missing (install Debian's 'assimp-utils')";
  const Variant& glb =
      *std::find_if(variants().begin(), variants().end(), [](const Variant& v) { return v.format == MeshFormat::glb; });
  for (const Shape& shape : shapes()) {
    SCOPED_TRACE(shape.name);
    const fs::path in = write(shape.mesh, shape.name, glb);
    std::string info;
    ASSERT_EQ(test::run("assimp info '" + in.string() + "'", &info), 0) << info;
    EXPECT_EQ(count_after(info, "Vertices:"), long(shape.mesh.num_vertices())) << info;
    EXPECT_EQ(count_after(info, "Faces:"), long(shape.mesh.num_faces())) << info;

    const fs::path out = dir() / (shape.name + "_assimp.obj");
    std::string log;
    ASSERT_EQ(test::run("assimp export '" + in.string() + "' '" + out.string() + "'", &log), 0) << log;
    const Soup s = cgal_soup(out);
    std::vector<Vec3> pts;
    for (const Point3& q : s.points) pts.push_back(vec(q));
    std::vector<std::array<long, 3>> tris;
    for (const auto& poly : s.polygons) {
      ASSERT_EQ(poly.size(), 3u);
      tris.push_back({long(poly[0]), long(poly[1]), long(poly[2])});
    }
    expect_same_geometry(pts, tris, shape.mesh, 1e-6 * bounding_box(shape.mesh).diagonal(), "assimp's OBJ");
  }
}

// Vertex colours of colored_tetra.ply survive PLY, OFF, OBJ, Draco and glTF.
TEST(RoundTrip, ColoursSurvive) {
  const Mesh m = read_mesh(test::sample("colored_tetra.ply"));
  ASSERT_EQ(m.num_vertices(), 4u);
  ASSERT_TRUE(m.has_colors());
  // The file's colours (red green blue, no alpha).
  const std::vector<Color> want = {{255, 255, 0, 255}, {0, 255, 255, 255}, {128, 0, 255, 255}, {255, 128, 0, 255}};
  ASSERT_EQ(m.colors, want);
  for (const Variant& v : variants()) {
    if (v.format == MeshFormat::stl) continue;  // STL has no colours
    SCOPED_TRACE(v.label);
    const fs::path p = write(m, "colours", v);
    const Mesh r = read_mesh(p);
    ASSERT_TRUE(r.has_colors());
    ASSERT_EQ(r.num_vertices(), 4u);
    // Vertex order may change (Draco): compare by position.
    const std::vector<long> to = match_points(r.positions, m, draco_tolerance(m));
    for (std::size_t i = 0; i < 4; ++i) {
      ASSERT_GE(to[i], 0);
      EXPECT_EQ(r.colors[i], m.colors[std::size_t(to[i])]) << "vertex " << i;
    }
  }
  // Alpha survives where the format has it (PLY, OFF, Draco, glTF; not OBJ).
  Mesh translucent = m;
  for (Color& c : translucent.colors) c.a = 100;
  for (const Variant& v : variants()) {
    if (v.format == MeshFormat::stl || v.format == MeshFormat::obj) continue;
    SCOPED_TRACE("alpha " + v.label);
    const Mesh r = read_mesh(write(translucent, "alpha", v));
    ASSERT_TRUE(r.has_colors());
    for (const Color& c : r.colors) EXPECT_EQ(c.a, 100);
  }
  // CGAL reads the colours of our PLY (binary and ascii) and OFF.
  for (const char* label : {"ply_binary", "ply_ascii"}) {
    SCOPED_TRACE(std::string("CGAL ") + label);
    const Variant& v =
        *std::find_if(variants().begin(), variants().end(), [&](const Variant& x) { return x.label == label; });
    const fs::path p = write(m, "colours_cgal", v);
    std::ifstream is(p, std::ios::binary);
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> polygons;
    std::vector<CGAL::IO::Color> fcolors, vcolors;
    ASSERT_TRUE(CGAL::IO::read_PLY(is, points, polygons, fcolors, vcolors));
    ASSERT_EQ(vcolors.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_EQ((std::array<int, 3>{vcolors[i].red(), vcolors[i].green(), vcolors[i].blue()}),
                (std::array<int, 3>{want[i].r, want[i].g, want[i].b}));
  }
  {
    const fs::path p = write(m, "colours_cgal", variants()[0]);
    std::vector<Point3> points;
    std::vector<std::vector<std::size_t>> polygons;
    std::vector<CGAL::IO::Color> vcolors;
    ASSERT_TRUE(
        CGAL::IO::read_OFF(p.string(), points, polygons,
                           CGAL::parameters::vertex_color_output_iterator(std::back_inserter(vcolors)).verbose(false)));
    ASSERT_EQ(vcolors.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i)
      EXPECT_EQ((std::array<int, 3>{vcolors[i].red(), vcolors[i].green(), vcolors[i].blue()}),
                (std::array<int, 3>{want[i].r, want[i].g, want[i].b}));
  }
}

// Colours whose components are all 0 or 1 (very dark) are not mistaken for
// 0..1 floats by the OFF reader.
TEST(RoundTrip, DarkColoursSurviveOff) {
  Mesh m = test::box();
  for (std::size_t i = 0; i < m.num_vertices(); ++i)
    m.colors.push_back({std::uint8_t(i & 1), std::uint8_t((i >> 1) & 1), 0, 255});
  const Mesh r = read_mesh_bytes(write_mesh_bytes(m, MeshFormat::off), MeshFormat::off, "dark.off").mesh;
  EXPECT_EQ(r.colors, m.colors);
}

// Per-vertex UVs survive OBJ and PLY exactly, Draco within its 12 bits and
// glTF within float rounding (glTF flips v twice).
TEST(RoundTrip, PerVertexUvsSurvive) {
  Mesh m = test::grid(4);
  for (const Vec3& p : m.positions) m.uvs.push_back({float(p.x / 4.0), float(p.y / 4.0) * 0.7f + 0.1f});
  for (const Variant& v : variants()) {
    if (v.format == MeshFormat::stl || v.format == MeshFormat::off)
      continue;  // no UVs in STL; OFF: see readers_test (STOFF)
    SCOPED_TRACE(v.label);
    const ReadResult r = read_mesh_file(write(m, "uvs", v));
    ASSERT_TRUE(r.mesh.has_uvs());
    ASSERT_TRUE(r.mesh.uv_faces.empty()) << "per-vertex UVs should stay per vertex";
    ASSERT_EQ(r.mesh.uvs.size(), m.num_vertices());
    const std::vector<long> to = match_points(r.mesh.positions, m, draco_tolerance(m));
    const double tol = v.format == MeshFormat::drc ? 2.0 / (1 << 12) : v.format == MeshFormat::glb ? 1e-6 : 0.0;
    for (std::size_t i = 0; i < m.num_vertices(); ++i) {
      ASSERT_GE(to[i], 0);
      const Vec2f want = m.uvs[std::size_t(to[i])], got = r.mesh.uvs[i];
      EXPECT_LE(std::abs(got.u - want.u), tol) << "vertex " << i;
      EXPECT_LE(std::abs(got.v - want.v), tol) << "vertex " << i;
    }
  }
}

// UVs with their own indices (a seam) survive OBJ as they are; PLY splits
// the seam's vertices into per-vertex UVs.
TEST(RoundTrip, SeparateUvIndicesSurviveObj) {
  Mesh m = test::box();
  // Each face of the cube gets the whole unit square: 4 uvs, per-corner indices.
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (std::size_t f = 0; f < m.num_faces(); ++f) m.uv_faces.push_back(f % 2 == 0 ? Tri{0, 1, 2} : Tri{0, 2, 3});
  m.normals = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 0, 0}};
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const Index n = Index(f / 2);
    m.normal_faces.push_back({n, n, n});
  }
  ASSERT_NO_THROW(m.validate());
  const std::string obj = write_mesh_bytes(m, MeshFormat::obj);
  EXPECT_NE(obj.find("f 1/1/1 3/2/1 2/3/1"), std::string::npos) << obj;
  const ReadResult r = read_mesh_bytes(obj, MeshFormat::obj, "seams.obj");
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.mesh.positions, m.positions);
  EXPECT_EQ(r.mesh.faces, m.faces);
  EXPECT_EQ(r.mesh.uvs, m.uvs);
  EXPECT_EQ(r.mesh.uv_faces, m.uv_faces);
  EXPECT_EQ(r.mesh.normals, m.normals);
  EXPECT_EQ(r.mesh.normal_faces, m.normal_faces);

  // PLY has per-vertex attributes only: the cube's corners are split.
  const Mesh ply = read_mesh_bytes(write_mesh_bytes(m, MeshFormat::ply), MeshFormat::ply, "seams.ply").mesh;
  EXPECT_EQ(ply.num_faces(), 12u);
  EXPECT_GT(ply.num_vertices(), 8u);
  EXPECT_TRUE(ply.uv_faces.empty());
  ASSERT_EQ(ply.uvs.size(), ply.num_vertices());
  for (std::size_t f = 0; f < 12; ++f)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(ply.positions[ply.faces[f][k]], m.positions[m.faces[f][k]]);
      EXPECT_EQ(ply.uvs[ply.faces[f][k]], m.uvs[m.uv_faces[f][k]]);
    }
}

// Normals survive OBJ (v//vn), PLY and glTF.
TEST(RoundTrip, NormalsSurvive) {
  Mesh m = test::uv_sphere(1.0, 8, 16);
  for (const Vec3& p : m.positions) m.normals.push_back(to_float(normalized(p)));
  for (const Variant& v : variants()) {
    if (v.format != MeshFormat::obj && v.format != MeshFormat::ply && v.format != MeshFormat::glb) continue;
    SCOPED_TRACE(v.label);
    const Mesh r = read_mesh(write(m, "normals", v));
    ASSERT_EQ(r.normals.size(), m.num_vertices());
    for (std::size_t i = 0; i < m.num_vertices(); ++i)
      EXPECT_LE(norm(to_double(r.normals[i]) - to_double(m.normals[i])), 1e-6) << i;
  }
}

// A sample STL (binary, from CGAL's data) converts to every format and back.
// It has non-manifold vertices, which Draco's edgebreaker splits: the .drc
// keeps every face but gains a vertex per extra fan.
TEST(RoundTrip, SampleStlConvertsEverywhere) {
  const ReadResult in = read_mesh_file(test::sample("pig.stl"));
  ASSERT_EQ(in.mesh.num_faces(), 16848u);
  ASSERT_EQ(in.mesh.num_vertices(), 8642u);
  const MeshReport report = mesh_report(in.mesh);
  ASSERT_EQ(report.non_manifold_vertices, 421u);
  for (const Variant& v : variants()) {
    SCOPED_TRACE(v.label);
    const Mesh r = read_mesh(write(in.mesh, "pig", v));
    EXPECT_EQ(r.num_faces(), in.mesh.num_faces());
    if (v.format == MeshFormat::drc) {
      EXPECT_GE(r.num_vertices(), in.mesh.num_vertices() + report.non_manifold_vertices);
      EXPECT_EQ(mesh_report(r).non_manifold_vertices, 0u);
    } else {
      EXPECT_EQ(r.num_vertices(), in.mesh.num_vertices());
    }
  }
}

// What a Surface_mesh sees of a round-tripped sample equals the original's.
TEST(RoundTrip, SurfaceMeshOfRoundTripMatches) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  const SurfaceMeshResult a = to_surface_mesh(m);
  for (const Variant& v : variants()) {
    SCOPED_TRACE(v.label);
    const SurfaceMeshResult b = to_surface_mesh(read_mesh(write(m, "elephant_sm", v)));
    EXPECT_EQ(b.skipped_faces, a.skipped_faces);
    EXPECT_EQ(b.mesh.number_of_vertices(), a.mesh.number_of_vertices());
    EXPECT_EQ(b.mesh.number_of_edges(), a.mesh.number_of_edges());
    EXPECT_EQ(b.mesh.number_of_faces(), a.mesh.number_of_faces());
    EXPECT_EQ(CGAL::is_closed(b.mesh), CGAL::is_closed(a.mesh));
  }
}

// A cloud of 500 points with normals and colours, written as a point cloud
// (vertices only) and read back by each format's reference reader and ours.
TEST(RoundTrip, APointCloudThroughPlyXyzAndDraco) {
  Mesh cloud;
  for (int i = 0; i < 500; ++i) {
    const double t = i * 0.1, z = -1 + 2 * (i + 0.5) / 500;
    cloud.positions.push_back({std::cos(t) * 3, std::sin(t) * 2, z});
    cloud.normals.push_back(normalized(Vec3f{float(std::cos(t)), float(std::sin(t)), 0.5f}));
    cloud.colors.push_back({std::uint8_t(i % 256), std::uint8_t(255 - i % 256), 7, 255});
  }
  const fs::path dir = test::temp_dir("round-trip-points");
  for (const char* ext : {"ply", "xyz", "drc"}) {
    SCOPED_TRACE(ext);
    const fs::path file = dir / (std::string("cloud.") + ext);
    write_mesh(cloud, file);
    const Mesh back = read_mesh(file);
    EXPECT_EQ(back.num_faces(), 0u);
    ASSERT_EQ(back.num_vertices(), 500u);
    EXPECT_EQ(back.normals.size(), 500u);
    EXPECT_EQ(back.colors.size(), std::string(ext) == "xyz" ? 0u : 500u);  // XYZ holds none
    const double tol = std::string(ext) == "drc" ? draco_tolerance(cloud) : 1e-6;
    for (std::size_t i = 0; i < 500; ++i) EXPECT_LE(norm(back.positions[i] - cloud.positions[i]), tol) << i;
    std::string log;
    if (std::string(ext) == "drc") {
      // Draco's own decoder, to PLY: every point in its place, in order.
      const fs::path out = dir / "cloud_decoded.ply";
      ASSERT_EQ(test::run("draco_decoder -i '" + file.string() + "' -o '" + out.string() + "'", &log), 0) << log;
      const Mesh decoded = read_mesh(out);
      ASSERT_EQ(decoded.num_vertices(), 500u);
      for (std::size_t i = 0; i < 500; ++i) EXPECT_LE(norm(decoded.positions[i] - cloud.positions[i]), tol) << i;
      continue;
    }
    ASSERT_TRUE(test::have_open3d()) << "/usr/bin/python3 has no open3d (install Debian's python3-open3d)";
    const auto o3d = test::open3d_read(file, std::string(ext) == "xyz" ? "xyzn" : "auto", &log);
    ASSERT_TRUE(o3d) << log;
    ASSERT_EQ((*o3d)["points"].size(), 500u);
    ASSERT_EQ((*o3d)["normals"].size(), 500u);
    for (std::size_t i = 0; i < 500; i += 7)
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR((*o3d)["points"][i][k].get<double>(), cloud.positions[i][k], tol) << i;
        EXPECT_NEAR((*o3d)["normals"][i][k].get<double>(), cloud.normals[i][k], 1e-6) << i;
      }
    if (std::string(ext) == "ply") {
      ASSERT_EQ((*o3d)["colors"].size(), 500u);
      EXPECT_NEAR((*o3d)["colors"][300][0].get<double>() * 255, cloud.colors[300].r, 1e-3);
    }
  }
}

}  // namespace
}  // namespace cgview
