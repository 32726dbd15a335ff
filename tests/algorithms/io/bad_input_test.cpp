// Malformed and hostile input for every format the readers accept: each case
// must end in a clean InvalidInput (a ParseError naming the file and the line
// or byte), never a crash, a hang, a huge allocation or another exception.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/errors.h"
#include "core/mesh.h"
#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "format_variants.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using test::box;
using test::uv_sphere;

using test::Variant;
using test::variants;

const Variant& variant(const std::string& label) {
  for (const Variant& v : variants())
    if (v.label == label) return v;
  throw std::logic_error("no variant " + label);
}

std::string encode(const Mesh& m, const Variant& v) {
  WriteOptions o;
  o.binary = v.binary;
  return write_mesh_bytes(m, v.format, o);
}

const fs::path& dir() {
  static const fs::path d = test::temp_dir("bad_input");
  return d;
}

// Writes bytes as DIR/TAG_LABEL.EXT.
fs::path put(const std::string& tag, const Variant& v, const std::string& bytes) {
  const fs::path p = dir() / (tag + "_" + v.label + "." + v.ext);
  test::write_text(p, bytes);
  return p;
}

std::size_t line_count(std::string_view text) { return std::size_t(std::count(text.begin(), text.end(), '\n')) + 1; }

// Reads a file expecting a ParseError that names it; any other outcome fails.
ParseError parse_error(const fs::path& p, const ReadOptions& options = {}) {
  try {
    const ReadResult r = read_mesh_file(p, options);
    ADD_FAILURE() << p << ": expected a ParseError, but it loaded " << r.mesh.num_vertices() << " vertices and "
                  << r.mesh.num_faces() << " faces";
  } catch (const ParseError& e) {
    EXPECT_EQ(e.file(), p.string());
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    EXPECT_FALSE(e.problem().empty());
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << p << ": expected a ParseError, got " << typeid(e).name() << ": " << e.what();
  }
  return ParseError(p.string(), "<no ParseError>", std::nullopt, std::nullopt);
}

// The text with line `line` (1-based) replaced.
std::string replace_line(const std::string& text, std::size_t line, const std::string& with) {
  std::size_t b = 0;
  for (std::size_t l = 1; l < line; ++l) b = text.find('\n', b) + 1;
  const std::size_t e = text.find('\n', b);
  return text.substr(0, b) + with + text.substr(e);
}
std::string get_line(const std::string& text, std::size_t line) {
  std::size_t b = 0;
  for (std::size_t l = 1; l < line; ++l) b = text.find('\n', b) + 1;
  return text.substr(b, text.find('\n', b) - b);
}
std::size_t header_size(const std::string& ply) { return ply.find("end_header\n") + 11; }
std::size_t header_lines(const std::string& ply) { return line_count(ply.substr(0, header_size(ply))) - 1; }

// The first line at or after `from` that starts (after blanks) with `key`,
// cut just after the token that follows the key: a record that stops early.
std::size_t cut_inside_record(const std::string& text, std::size_t from, const std::string& key) {
  std::size_t b = text.rfind('\n', from);
  b = b == std::string::npos ? 0 : b + 1;
  for (;;) {
    std::size_t p = b;
    while (text[p] == ' ' || text[p] == '\t') ++p;
    if (text.compare(p, key.size(), key) == 0) {
      p += key.size();
      while (text[p] == ' ') ++p;
      while (p < text.size() && text[p] != ' ' && text[p] != '\n') ++p;
      return p;
    }
    b = text.find('\n', b) + 1;
    if (b == 0 || b >= text.size()) throw std::logic_error("no record " + key);
  }
}

long peak_rss_kb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss;
}

template <class T>
void put_raw(std::string& s, std::size_t at, T v) {
  ASSERT_LE(at + sizeof(T), s.size());
  std::memcpy(s.data() + at, &v, sizeof(T));
}

// Three triangles on the edge (0, 1): loads as is, reported non-manifold.
Mesh three_on_an_edge() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

// ---------------------------------------------------------------------------

TEST(BadInput, EmptyFileIsAParseErrorNamingTheFile) {
  for (const Variant& v : variants()) {
    SCOPED_TRACE(v.label);
    const ParseError e = parse_error(put("empty", v, ""));
    const std::string what = e.what();
    EXPECT_TRUE(what.find("empty") != std::string::npos || what.find("no vertices") != std::string::npos) << what;
    // Text formats that need a first line say where.
    if (v.format == MeshFormat::off || v.format == MeshFormat::ply) {
      EXPECT_EQ(e.line(), 1u) << what;
    }
  }
}

TEST(BadInput, TruncatedFileSaysWhereItEnds) {
  const Mesh m = uv_sphere(1.0, 8, 16);
  for (const Variant& v : variants()) {
    SCOPED_TRACE(v.label);
    const std::string full = encode(m, v);
    std::size_t cut = full.size() / 2;
    // OBJ has no counts and ascii STL may end between facets: cut inside a record.
    if (v.format == MeshFormat::obj) cut = cut_inside_record(full, cut, "v ");
    if (v.label == "stl_ascii") cut = cut_inside_record(full, cut, "vertex");
    const std::string half = full.substr(0, cut);
    const ParseError e = parse_error(put("truncated", v, half));
    if (v.text()) {
      ASSERT_TRUE(e.line().has_value()) << e.what();
      EXPECT_EQ(*e.line(), line_count(half)) << e.what();  // the error is where the bytes stop
      EXPECT_FALSE(e.byte_offset().has_value());
      EXPECT_NE(std::string(e.what()).find("line " + std::to_string(*e.line()) + ":"), std::string::npos) << e.what();
    } else if (v.format == MeshFormat::ply || v.format == MeshFormat::stl) {
      ASSERT_TRUE(e.byte_offset().has_value()) << e.what();
      EXPECT_LE(*e.byte_offset(), half.size()) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte " + std::to_string(*e.byte_offset()) + ":"), std::string::npos)
          << e.what();
    }
  }
  // Binary STL: the size does not match the header's triangle count (byte 80).
  const std::string stl = encode(m, variant("stl_binary"));
  const ParseError e = parse_error(put("truncated2", variant("stl_binary"), stl.substr(0, stl.size() - 7)));
  EXPECT_EQ(e.byte_offset(), 80u) << e.what();
  EXPECT_NE(std::string(e.what()).find(std::to_string(m.num_faces()) + " triangles"), std::string::npos) << e.what();
}

TEST(BadInput, AsciiStlCutBetweenFacetsLoadsWithAWarning) {
  // Documented: no endsolid is a warning, the complete facets are kept.
  const std::string full = encode(box(), variant("stl_ascii"));
  std::size_t cut = 0;
  for (int k = 0; k < 5; ++k) cut = full.find("endfacet\n", cut) + 9;
  const ReadResult r = read_mesh_bytes(full.substr(0, cut), MeshFormat::stl, "cut.stl");
  EXPECT_EQ(r.mesh.num_faces(), 5u);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings.back().find("endsolid"), std::string::npos) << r.warnings.back();
}

TEST(BadInput, BinaryGarbageIsRefusedAtTheStart) {
  std::mt19937 rng(20240611);
  std::string garbage(4096, '\0');
  for (char& c : garbage) c = char(rng() & 0xff);
  for (const Variant& v : variants()) {
    if (v.label == "ply_ascii" || v.label == "stl_ascii") continue;  // same bytes as the binary variant
    SCOPED_TRACE(v.label);
    const ParseError e = parse_error(put("garbage", v, garbage));
    switch (v.format) {
      case MeshFormat::off:
      case MeshFormat::ply:
        EXPECT_EQ(e.line(), 1u) << e.what();
        EXPECT_NE(std::string(e.what()).find("not a"), std::string::npos) << e.what();
        break;
      case MeshFormat::obj:
        ASSERT_TRUE(e.line().has_value()) << e.what();
        EXPECT_NE(std::string(e.what()).find("binary data"), std::string::npos) << e.what();
        break;
      case MeshFormat::stl:
        EXPECT_EQ(e.byte_offset(), 80u) << e.what();
        break;
      case MeshFormat::drc:
      case MeshFormat::glb:
        EXPECT_EQ(e.byte_offset(), 0u) << e.what();
        break;
      default:
        break;
    }
  }
}

TEST(BadInput, NonFiniteCoordinatesInTextFormats) {
  // The first coordinate of vertex 3 (0-based) becomes each bad token; the
  // last, an exponent of INT64_MAX, overflowed the exponent's sum (found by
  // fuzz_stl: tests/fuzz/corpus/stl/regression-exponent-overflow) and read as 0.
  const Mesh m = box();
  for (const std::string bad :
       {"nan", "inf", "-inf", "1e400", "-1e400", "NaN", "3223678218291318148E9223372036854775807"}) {
    SCOPED_TRACE(bad);
    {
      const std::string text = encode(m, variant("off"));
      const std::size_t line = 3 + 3;  // OFF, counts, vertices 0..2
      const std::string y_z = get_line(text, line).substr(get_line(text, line).find(' '));
      const ParseError e = parse_error(put("nonfinite", variant("off"), replace_line(text, line, bad + y_z)));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("vertex 3 has a non-finite coordinate"), std::string::npos) << e.what();
    }
    {
      const std::string text = encode(m, variant("obj"));
      const std::size_t line = 2 + 3;  // a comment, vertices 1..3
      const std::string y_z = get_line(text, line).substr(get_line(text, line).find(' ', 2));
      const ParseError e = parse_error(put("nonfinite", variant("obj"), replace_line(text, line, "v " + bad + y_z)));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("vertex 4 has a non-finite coordinate"), std::string::npos) << e.what();
    }
    {
      const std::string text = encode(m, variant("ply_ascii"));
      const std::size_t line = header_lines(text) + 1 + 3;
      const std::string y_z = get_line(text, line).substr(get_line(text, line).find(' '));
      const ParseError e = parse_error(put("nonfinite", variant("ply_ascii"), replace_line(text, line, bad + y_z)));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("vertex 3 has a non-finite coordinate"), std::string::npos) << e.what();
    }
    {
      const std::string text = encode(m, variant("stl_ascii"));
      // solid, facet 0: facet normal, outer loop, vertex, vertex, vertex: line 5 is corner 1 of facet 0.
      const std::size_t line = 5;
      ASSERT_NE(get_line(text, line).find("vertex"), std::string::npos);
      const ParseError e =
          parse_error(put("nonfinite", variant("stl_ascii"), replace_line(text, line, "  vertex 0 " + bad + " 1")));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("non-finite"), std::string::npos) << e.what();
    }
  }
}

TEST(BadInput, NonFiniteCoordinatesInBinaryFormatsGiveTheByteOffset) {
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -std::numeric_limits<float>::infinity()};
  for (float b : bad) {
    SCOPED_TRACE(b);
    {  // Binary PLY, positions only (12 bytes a vertex): vertex 5's y.
      std::string ply = encode(box(), variant("ply_binary"));
      const std::size_t at = header_size(ply) + 5 * 12;
      put_raw(ply, at + 4, b);
      const ParseError e = parse_error(put("nonfinite", variant("ply_binary"), ply));
      EXPECT_EQ(e.byte_offset(), at) << e.what();
      EXPECT_NE(std::string(e.what()).find("vertex 5 has a non-finite coordinate"), std::string::npos) << e.what();
    }
    {  // Binary PLY with colours (16 bytes a vertex): vertex 2's z.
      Mesh m = box();
      m.colors.assign(m.num_vertices(), Color{10, 20, 30, 255});
      std::string ply = encode(m, variant("ply_binary"));
      const std::size_t at = header_size(ply) + 2 * 16;
      put_raw(ply, at + 8, b);
      const ParseError e = parse_error(put("nonfinite_colour", variant("ply_binary"), ply));
      EXPECT_EQ(e.byte_offset(), at) << e.what();
      EXPECT_NE(std::string(e.what()).find("vertex 2 has a non-finite coordinate"), std::string::npos) << e.what();
    }
    {  // Binary STL: triangle 3, corner 1.
      std::string stl = encode(box(), variant("stl_binary"));
      const std::size_t at = 84 + 50 * 3 + 12 + 12 * 1;
      put_raw(stl, at, b);
      const ParseError e = parse_error(put("nonfinite", variant("stl_binary"), stl));
      EXPECT_EQ(e.byte_offset(), at) << e.what();
      EXPECT_NE(std::string(e.what()).find("triangle 3 has a non-finite coordinate"), std::string::npos) << e.what();
    }
  }
}

TEST(BadInput, IndexOutOfRangeNamesTheFaceAndTheIndex) {
  const Mesh m = box();
  {
    const std::string text = encode(m, variant("off"));
    const std::size_t line = 2 + 8 + 4;  // face 3
    ASSERT_EQ(get_line(text, line).substr(0, 2), "3 ");
    for (const std::string idx : {"8", "-1", "4294967296"}) {
      SCOPED_TRACE("off " + idx);
      const ParseError e = parse_error(put("index", variant("off"), replace_line(text, line, "3 1 " + idx + " 2")));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("face 3 refers to vertex " + idx), std::string::npos) << e.what();
    }
  }
  {
    const std::string text = encode(m, variant("obj"));
    const std::size_t line = 1 + 8 + 4;  // face 3
    ASSERT_EQ(get_line(text, line).substr(0, 2), "f ");
    for (const std::string idx : {"9", "-9", "0"}) {
      SCOPED_TRACE("obj " + idx);
      const ParseError e = parse_error(put("index", variant("obj"), replace_line(text, line, "f 2 " + idx + " 3")));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("face 3 refers to vertex " + idx), std::string::npos) << e.what();
    }
    // Texture and normal indices too.
    const ParseError e = parse_error(put("index_vt", variant("obj"), replace_line(text, line, "f 2/1 3/1 4/1")));
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find("face 3 refers to texture coordinate 1"), std::string::npos) << e.what();
  }
  {
    const std::string text = encode(m, variant("ply_ascii"));
    const std::size_t line = header_lines(text) + 8 + 4;  // face 3
    // 1e+75: no integer holds it, and the message cast it to one (fuzz_ply,
    // tests/fuzz/corpus/ply/regression-index-1e75).
    for (const std::string idx : {"8", "-1", "1e+75"}) {
      SCOPED_TRACE("ply ascii " + idx);
      const ParseError e =
          parse_error(put("index", variant("ply_ascii"), replace_line(text, line, "3 1 " + idx + " 2")));
      EXPECT_EQ(e.line(), line) << e.what();
      EXPECT_NE(std::string(e.what()).find("face 3 refers to vertex " + idx), std::string::npos) << e.what();
    }
  }
  {
    std::string ply = encode(m, variant("ply_binary"));
    const std::size_t face3 = header_size(ply) + 8 * 12 + 3 * 13;  // uchar count + 3 ints a face
    for (std::int32_t idx : {8, -1, 1 << 30}) {
      SCOPED_TRACE("ply binary " + std::to_string(idx));
      put_raw(ply, face3 + 1 + 4, idx);
      const ParseError e = parse_error(put("index", variant("ply_binary"), ply));
      ASSERT_TRUE(e.byte_offset().has_value()) << e.what();
      EXPECT_GE(*e.byte_offset(), face3) << e.what();
      EXPECT_LE(*e.byte_offset(), face3 + 13) << e.what();
      EXPECT_NE(std::string(e.what()).find("face 3 refers to vertex " + std::to_string(idx)), std::string::npos)
          << e.what();
    }
  }
}

TEST(BadInput, LyingHeaderCountsAreRefusedQuicklyWithoutAllocating) {
  const long rss_before = peak_rss_kb();
  const auto t0 = std::chrono::steady_clock::now();
  const std::string body = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  struct Case {
    std::string tag, label, bytes, says;
    std::optional<std::uint64_t> line, offset;
  };
  std::vector<Case> cases = {
      {"off_1e12", "off", "OFF\n1000000000000 1 0\n" + body, "over 4 billion", 2, std::nullopt},
      {"off_4e9", "off", "OFF\n4000000000 1 0\n" + body, "the header claims 4000000000 vertices", 2, std::nullopt},
      {"off_faces", "off", "OFF\n3 4000000000 0\n" + body, "the header claims 4000000000 faces", 2, std::nullopt},
      {"off_corners", "off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n", "claims 1000000000 corners", 6,
       std::nullopt},
      {"ply_1e12", "ply_ascii",
       "ply\nformat ascii 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\nproperty float z\n"
       "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
           body,
       "the header claims 1000000000000 vertex elements", 9, std::nullopt},
      {"ply_1e12", "ply_binary",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n" +
           std::string(36, '\0'),
       "the header claims 1000000000000 vertex elements", 7, std::nullopt},
      {"ply_faces", "ply_binary",
       "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1000000000000\nproperty list uint int vertex_indices\nend_header\n" +
           std::string(64, '\0'),
       "the header claims 1000000000000 face elements", 9, std::nullopt},
      {"ply_no_props", "ply_binary",  // an element without properties costs no bytes
       "ply\nformat binary_little_endian 1.0\nelement vertex 0\nproperty float x\nproperty float y\n"
       "property float z\nelement junk 1000000000000\nend_header\n",
       "", std::nullopt, std::nullopt},
      {"stl_4e9", "stl_binary",
       [] {
         std::string s(84 + 50, '\0');
         const std::uint32_t n = 4000000000u;
         std::memcpy(s.data() + 80, &n, 4);
         return s;
       }(),
       "claims 4000000000 triangles", std::nullopt, 80},
  };
  {  // A binary PLY face whose list claims 4e9 corners.
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n";
    const std::size_t face = ply.size() + 36;
    ply += std::string(36 + 4 + 12, '\0');
    const std::uint32_t n = 4000000000u;
    std::memcpy(ply.data() + face, &n, 4);
    cases.push_back({"ply_list", "ply_binary", ply, "a list claims 4000000000 items", std::nullopt, face + 4});
  }
  {  // An ascii PLY list length that no integer type holds.
    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
    cases.push_back({"ply_list_1e30", "ply_ascii", ply + "1e30 0 1 2\n", "a list claims", 13, std::nullopt});
    cases.push_back({"ply_list_inf", "ply_ascii", ply + "inf 0 1 2\n", "list", 13, std::nullopt});
    cases.push_back(
        {"ply_list_2e19", "ply_ascii", ply + "20000000000000000000 0 1 2\n", "a list claims", 13, std::nullopt});
  }
  for (const Case& c : cases) {
    SCOPED_TRACE(c.tag + " " + c.label);
    const auto start = std::chrono::steady_clock::now();
    const fs::path p = put(c.tag, variant(c.label), c.bytes);
    if (c.says.empty()) {  // loads: the element is skipped, not iterated a trillion times
      ReadResult r;
      EXPECT_NO_THROW(r = read_mesh_file(p));
      EXPECT_EQ(r.mesh.num_vertices(), 0u);
    } else {
      const ParseError e = parse_error(p);
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_EQ(e.byte_offset(), c.offset) << e.what();
    }
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 0.5);
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 2.0);
  EXPECT_LT(peak_rss_kb() - rss_before, 100 * 1024) << "peak RSS grew by " << (peak_rss_kb() - rss_before) << " KiB";
}

// Draco's edgebreaker decoder sizes its corner table (several 4-byte
// indices a corner) for the face count the header claims before a byte backs
// it: 33 bytes claiming 1.4 billion faces ask for tens of GB.  The counts are
// checked first.
TEST(BadInput, LyingDracoCountsAreRefusedBeforeDracoAllocates) {
  const long rss_before = peak_rss_kb();
  const auto t0 = std::chrono::steady_clock::now();
  struct Case {
    std::string tag;
    std::string bytes, says;
  };
  const std::vector<Case> cases = {
      {"faces", test::draco_claiming(1400000000),
       "the Draco header claims 1400000000 faces, but 33 bytes cannot hold more"},
      {"vertices", test::draco_claiming(1000, 4000000), "claims 4000000 vertices for 1000 faces"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.tag);
    const fs::path p = dir() / ("claims_" + c.tag + ".drc");
    test::write_text(p, c.bytes);
    const ParseError e = parse_error(p);
    EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.5);
  EXPECT_LT(peak_rss_kb() - rss_before, 100 * 1024) << "peak RSS grew by " << (peak_rss_kb() - rss_before) << " KiB";
}

// The fuzzer's first finding (tests/fuzz/corpus/drc/regression-bool-attribute):
// a Draco stream whose positions are of type bool; Draco converted them by
// loading a byte of 14 as a bool, undefined behaviour.
TEST(BadInput, DracoAttributesThatAreNotNumbersAreRefused) {
  const std::string bytes(
      "\x44\x52\x41\x43\x4f\x02\x02\x01\x01\x00\x00\x00\x08\x0c\x00\x0b\x00\x00\x03\x6f\x55\x15\x01\x01"
      "\x10\x01\xff\x00\x00\x01\x00\x0b\x01\x20\x03\x00\x38\x41\x0e\x05\x05\x44\x02\x01\x00\x3f\xd3\x00"
      "\xff\x00\x01\x55\x15\x01\x01\x18\x01\xff\x00\x00\x00\x80\x40\xff\x00\x00\x40\x0e",
      68);
  const fs::path p = dir() / "bool_positions.drc";
  test::write_text(p, bytes);
  const ParseError e = parse_error(p);
  EXPECT_NE(std::string(e.what()).find("the Draco positions are of data type 11, not numbers"), std::string::npos)
      << e.what();
}

// The bound is 1024 faces a byte of the stream (draco_io.cpp): a regular
// grid at Draco's best compression and 1-bit positions (its every vertex
// predicted exactly), denser than any scanned mesh by far, stays under it and
// loads.
TEST(BadInput, TheDensestHonestDracoStreamIsUnderTheBoundAndLoads) {
  const Mesh g = test::grid(800);  // 1.28 million faces
  WriteOptions o;
  o.draco_speed = 0;
  o.position_bits = 1;
  const std::string bytes = write_mesh_bytes(g, MeshFormat::drc, o);
  const double per_byte = double(g.num_faces()) / double(bytes.size());
  RecordProperty("faces_per_byte", std::to_string(per_byte));
  std::printf("grid(800): %zu faces in %zu bytes, %.2f faces a byte\n", g.num_faces(), bytes.size(), per_byte);
  EXPECT_GT(per_byte, 100.0) << "no longer the densest stream this test means to check";
  EXPECT_LT(per_byte, 1024.0) << "the bound refuses an honest stream";
  EXPECT_EQ(read_mesh_bytes(bytes, MeshFormat::drc, "grid.drc").mesh.num_faces(), g.num_faces());
}

// Dumping a JSON value recurses once a level: a glTF whose indices were an
// array nested 200,000 deep crashed the reader's error message.
TEST(BadInput, DeeplyNestedGltfJsonIsRefusedNotACrash) {
  const std::size_t depth = 200000;
  const std::string doc =
      R"({"asset":{"version":"2.0"},"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":)" +
      std::string(depth, '[') + std::string(depth, ']') + "}]}]}";
  const fs::path p = dir() / "deep.gltf";
  test::write_text(p, doc);
  const ParseError e = parse_error(p);
  EXPECT_NE(std::string(e.what()).find("nests arrays and objects 200005 deep; at most 64 are read"), std::string::npos)
      << e.what();
}

TEST(BadInput, NonManifoldMeshLoadsAndIsReportedNonManifold) {
  const Mesh m = three_on_an_edge();
  ASSERT_EQ(mesh_report(m).non_manifold_edges, 1u);
  for (const Variant& v : variants()) {
    SCOPED_TRACE(v.label);
    const fs::path p = put("non_manifold", v, encode(m, v));
    ReadResult r;
    ASSERT_NO_THROW(r = read_mesh_file(p));
    EXPECT_NO_THROW(r.mesh.validate());
    EXPECT_EQ(r.mesh.num_faces(), 3u);
    const MeshReport rep = mesh_report(r.mesh);
    if (v.format == MeshFormat::drc) {
      // Draco's edgebreaker stores a non-manifold edge by splitting its
      // vertices: the faces survive, the shared edge does not.
      EXPECT_GT(r.mesh.num_vertices(), 5u);
      EXPECT_EQ(rep.non_manifold_edges, 0u);
      EXPECT_GT(rep.components, 1u);
      continue;
    }
    EXPECT_EQ(r.mesh.num_vertices(), 5u);
    EXPECT_FALSE(rep.manifold);
    EXPECT_EQ(rep.non_manifold_edges, 1u);
  }
}

TEST(BadInput, UnknownExtensionIsUnsupportedFormatNamingIt) {
  const fs::path p = dir() / "mesh.las";
  test::write_text(p, "OFF\n0 0 0\n");
  try {
    read_mesh_file(p);
    ADD_FAILURE() << "no exception";
  } catch (const UnsupportedFormat& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(".las"), std::string::npos) << what;
    EXPECT_NE(what.find(p.string()), std::string::npos) << what;
    EXPECT_NE(what.find("off, obj, ply, stl, drc, glb"), std::string::npos) << what;
  }
  EXPECT_THROW(read_mesh_file(dir() / "no_extension"), UnsupportedFormat);
  EXPECT_THROW(write_mesh(box(), dir() / "out.las"), UnsupportedFormat);
  try {
    write_mesh(box(), dir() / "out.gltf");
    ADD_FAILURE() << "wrote gltf";
  } catch (const UnsupportedFormat& e) {
    EXPECT_NE(std::string(e.what()).find("gltf"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir() / "out.gltf"));
  EXPECT_FALSE(fs::exists(dir() / "out.las"));
}

TEST(BadInput, DirectoryOrMissingFileIsAnIoError) {
  const fs::path d = dir() / "a_directory.off";
  fs::create_directories(d);
  const fs::path missing = dir() / "missing.ply";
  for (const fs::path& p : {d, missing}) {
    SCOPED_TRACE(p.string());
    try {
      read_mesh_file(p);
      ADD_FAILURE() << "no exception";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << typeid(e).name() << ": " << e.what();
    }
  }
  // Writing into a directory that does not exist.
  EXPECT_THROW(write_mesh(box(), dir() / "no" / "such" / "dir.off"), IoError);
}

TEST(BadInput, FileOverTheSizeLimitIsRefusedBeforeReading) {
  const fs::path p = put("big", variant("off"), encode(uv_sphere(), variant("off")));
  ReadOptions o;
  o.max_bytes = 1000;
  try {
    read_mesh_file(p, o);
    ADD_FAILURE() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("limit of 1000"), std::string::npos) << e.what();
  }
  EXPECT_THROW(read_mesh_bytes(std::string(2000, ' '), MeshFormat::off, "x.off", o), InvalidInput);
}

// Debian's assimp-testmodels: files that once crashed assimp's loaders.
TEST(BadInput, AssimpInvalidModels) {
  struct Expect {
    std::string file, says;
    std::optional<std::uint64_t> line;
  };
  const std::vector<Expect> known = {
      {"/usr/share/assimp/models/invalid/empty.obj", "no vertices", std::nullopt},
      {"/usr/share/assimp/models/invalid/empty.off", "empty", 1},
      {"/usr/share/assimp/models/invalid/empty.ply", "empty", 1},
      {"/usr/share/assimp/models/invalid/malformed.obj", "face 0 refers to vertex 12 but 8 are defined", 23},
      {"/usr/share/assimp/models/invalid/malformed2.obj", "a face has 0 corners", 23},
      {"/usr/share/assimp/models/invalid/OutOfMemory.off", "over 4 billion", 2},
      {"/usr/share/assimp/models/OFF/invalid.off", "face 0 has 0 corners", 6},
  };
  for (const Expect& x : known) {
    SCOPED_TRACE(x.file);
    if (!fs::exists(x.file)) {
      ADD_FAILURE() << "missing " << x.file << " (install Debian's assimp-testmodels)";
      continue;
    }
    const ParseError e = parse_error(x.file);
    EXPECT_NE(std::string(e.what()).find(x.says), std::string::npos) << e.what();
    EXPECT_EQ(e.line(), x.line) << e.what();
  }
  // Any other file there with an extension we read: a clean error or a valid mesh.
  for (const fs::path root : {"/usr/share/assimp/models/invalid", "/usr/share/assimp/models/OFF"}) {
    if (!fs::is_directory(root)) continue;
    for (const auto& entry : fs::directory_iterator(root)) {
      const fs::path& p = entry.path();
      MeshFormat f;
      try {
        f = format_from_name(p.string());
      } catch (const UnsupportedFormat&) {
        continue;
      }
      (void)f;
      SCOPED_TRACE(p.string());
      try {
        const ReadResult r = read_mesh_file(p);
        EXPECT_NO_THROW(r.mesh.validate());
      } catch (const InvalidInput& e) {
        EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
      } catch (const std::exception& e) {
        ADD_FAILURE() << typeid(e).name() << ": " << e.what();
      }
    }
  }
}

// Truncations at every length and random byte changes: each read returns a
// mesh that validates or throws InvalidInput; nothing else escapes.
class Fuzz : public ::testing::TestWithParam<std::string> {};

TEST_P(Fuzz, TruncatedOrFlippedBytesNeverEscapeAsAnotherError) {
  const Variant& v = variant(GetParam());
  Mesh m = box();
  if (v.format == MeshFormat::ply || v.format == MeshFormat::off) {
    m.colors.assign(m.num_vertices(), Color{200, 100, 50, 255});
  }
  const std::string valid = encode(m, v);
  const std::string name = "fuzz." + v.ext;
  int failures = 0, loaded = 0, refused = 0;
  auto check = [&](const std::string& bytes, const std::string& what) {
    if (failures > 5) return;
    try {
      const ReadResult r = read_mesh_bytes(bytes, v.format, name);
      ++loaded;
      try {
        r.mesh.validate();
      } catch (const std::exception& e) {
        ++failures;
        ADD_FAILURE() << what << ": loaded a mesh that does not validate: " << e.what();
      }
    } catch (const InvalidInput& e) {
      ++refused;
      if (std::string(e.what()).find(name) == std::string::npos) {
        ++failures;
        ADD_FAILURE() << what << ": the message does not name the file: " << e.what();
      }
    } catch (const std::exception& e) {
      ++failures;
      ADD_FAILURE() << what << ": " << typeid(e).name() << " escaped: " << e.what();
    } catch (...) {
      ++failures;
      ADD_FAILURE() << what << ": a non-standard exception escaped";
    }
  };
  ASSERT_NO_THROW(read_mesh_bytes(valid, v.format, name));
  for (std::size_t n = 0; n < valid.size(); ++n) check(valid.substr(0, n), "truncated to " + std::to_string(n));
  std::mt19937 rng(12345);
  for (int k = 0; k < 400; ++k) {
    std::string bytes = valid;
    const int changes = 1 + int(rng() % 4);
    std::string what = "changed";
    for (int c = 0; c < changes; ++c) {
      const std::size_t at = rng() % bytes.size();
      const char to = (rng() % 3 == 0) ? "0123456789 -.\n"[rng() % 14] : char(rng() & 0xff);
      bytes[at] = to;
      what += " byte " + std::to_string(at) + "=" + std::to_string(int(static_cast<unsigned char>(to)));
    }
    check(bytes, what);
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GT(refused, 0);
  EXPECT_GT(loaded, 0);  // some variants are still valid files
}

INSTANTIATE_TEST_SUITE_P(BadInput, Fuzz, ::testing::ValuesIn([] {
                           std::vector<std::string> labels;
                           for (const Variant& v : variants()) labels.push_back(v.label);
                           return labels;
                         }()),
                         [](const ::testing::TestParamInfo<std::string>& info) { return info.param; });

}  // namespace
}  // namespace cgview
