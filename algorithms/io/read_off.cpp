// OFF (Geomview's Object File Format), with the optional ST, C, N and 4
// prefixes on the keyword, as CGAL and MeshLab write it.
#include <cmath>

#include "io/readers.h"
#include "io/text_scanner.h"

namespace cgview::detail {

namespace {
std::uint8_t colour_byte(double c, bool as_float) {
  double v = as_float ? c * 255.0 : c;
  return std::uint8_t(std::clamp(std::lround(v), 0L, 255L));
}
}  // namespace

void read_off(std::string_view bytes, const std::string& name, ReadResult& result) {
  TextScanner in(bytes, name);
  Mesh& mesh = result.mesh;
  in.skip_space();
  if (in.at_end()) in.fail("the file is empty");
  const char* key_pos = in.pos();
  std::string_view key = in.word();
  // [ST][C][N][4][n]OFF
  bool has_st = false, has_c = false, has_n = false, homogeneous = false;
  std::string_view k = key;
  if (k.starts_with("ST")) {
    has_st = true;
    k.remove_prefix(2);
  }
  if (k.starts_with("C")) {
    has_c = true;
    k.remove_prefix(1);
  }
  if (k.starts_with("N")) {
    has_n = true;
    k.remove_prefix(1);
  }
  if (k.starts_with("4")) {
    homogeneous = true;
    k.remove_prefix(1);
  }
  if (k.starts_with("n")) in.fail_at(key_pos, "OFF files of other dimensions than 3 (nOFF) are not supported");
  if (k != "OFF")
    in.fail_at(key_pos, "not an OFF file: it starts with " + std::string(key.substr(0, 24)) + ", not OFF");
  if (in.word() == "BINARY") in.fail_at(key_pos, "binary OFF is not supported; convert it to ascii OFF or PLY");
  in.set_pos(key_pos + key.size());

  in.skip_space();
  const char* counts_pos = in.pos();
  const std::int64_t nv = in.need_int("the number of vertices");
  in.skip_space();
  const std::int64_t nf = in.need_int("the number of faces");
  std::int64_t ne = 0;
  if (!in.at_eol()) in.try_int(ne);
  const std::uint64_t line = in.line_at(counts_pos);
  if (nv < 0 || nf < 0) in.fail_at(counts_pos, "negative vertex or face count");
  if (nv > std::int64_t(UINT32_MAX) - 1 || nf > std::int64_t(UINT32_MAX) - 1)
    in.fail_at(counts_pos, "over 4 billion vertices or faces");
  // A vertex needs at least "0 0 0\n" (6 bytes), a face "3 0 0 0\n" (8).
  check_claim(std::uint64_t(nv), 6, in.remaining(), "vertices", name, line);
  check_claim(std::uint64_t(nf), 8, in.remaining(), "faces", name, line);
  in.skip_line();

  mesh.positions.resize(std::size_t(nv));
  if (has_n) mesh.normals.resize(std::size_t(nv));
  if (has_st) mesh.uvs.resize(std::size_t(nv));
  bool colour_float = false;
  std::vector<std::array<double, 4>> raw_colours;
  if (has_c) raw_colours.resize(std::size_t(nv));
  for (std::int64_t v = 0; v < nv; ++v) {
    in.skip_space();
    Vec3 p;
    for (int i = 0; i < 3; ++i) p[i] = in.need_double("a vertex coordinate");
    if (homogeneous) {
      double w = in.need_double("the homogeneous coordinate");
      p = p / w;
    }
    if (!is_finite(p)) in.fail("vertex " + std::to_string(v) + " has a non-finite coordinate");
    mesh.positions[std::size_t(v)] = p;
    if (has_n) {
      Vec3f& n = mesh.normals[std::size_t(v)];
      for (int i = 0; i < 3; ++i) n[i] = float(in.need_double("a normal coordinate"));
    }
    if (has_c) {
      auto& c = raw_colours[std::size_t(v)];
      c = {0, 0, 0, -1};
      for (int i = 0; i < 3; ++i) c[i] = in.need_double("a colour component");
      double a;
      if (!in.at_eol() && in.try_double(a)) c[3] = a;
      for (double x : c)
        if (x != std::floor(x) && x >= 0) colour_float = true;
    }
    if (has_st) {
      Vec2f& t = mesh.uvs[std::size_t(v)];
      t.u = float(in.need_double("a texture coordinate"));
      t.v = float(in.need_double("a texture coordinate"));
    }
    if (!in.at_eol()) in.fail("unexpected " + in.describe_here() + " after vertex " + std::to_string(v));
  }
  if (has_c) {
    // Components are 0..255 integers or 0..1 floats; a file picks one.
    bool all_small = true;
    for (const auto& c : raw_colours)
      for (int i = 0; i < 3; ++i) all_small &= c[i] <= 1.0;
    colour_float = colour_float || all_small;
    mesh.colors.resize(raw_colours.size());
    for (std::size_t v = 0; v < raw_colours.size(); ++v) {
      const auto& c = raw_colours[v];
      mesh.colors[v] = {colour_byte(c[0], colour_float), colour_byte(c[1], colour_float),
                        colour_byte(c[2], colour_float),
                        c[3] < 0 ? std::uint8_t(255) : colour_byte(c[3], colour_float)};
    }
  }

  mesh.faces.reserve(std::size_t(nf));
  std::vector<Index> poly;
  std::uint64_t polygons = 0;
  for (std::int64_t f = 0; f < nf; ++f) {
    in.skip_space();
    const char* face_pos = in.pos();
    const std::int64_t n = in.need_int("the number of corners of a face");
    if (n < 3)
      in.fail_at(face_pos, "face " + std::to_string(f) + " has " + std::to_string(n) + " corners (at least 3 needed)");
    if (std::uint64_t(n) > in.remaining() / 2)
      in.fail_at(face_pos,
                 "face " + std::to_string(f) + " claims " + std::to_string(n) + " corners, more than the file holds");
    poly.clear();
    for (std::int64_t i = 0; i < n; ++i) {
      const std::int64_t idx = in.need_int("a vertex index");
      if (idx < 0 || idx >= nv)
        in.fail("face " + std::to_string(f) + " refers to vertex " + std::to_string(idx) + " but there are " +
                std::to_string(nv) + " vertices");
      poly.push_back(Index(idx));
    }
    in.skip_line();  // a face colour may follow
    if (n > 3) ++polygons;
    for (std::size_t i = 1; i + 1 < poly.size(); ++i) mesh.faces.push_back({poly[0], poly[i], poly[i + 1]});
  }
  in.skip_space();
  if (!in.at_end() && nf > 0)
    result.warnings.push_back("ignored data after the last face (line " + std::to_string(in.line_at(in.pos())) + ")");
  if (polygons) result.warnings.push_back(std::to_string(polygons) + " polygons were split into triangles");
}

}  // namespace cgview::detail
