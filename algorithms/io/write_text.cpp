// Writers for OFF, OBJ, PLY and STL.  Numbers are written with
// std::to_chars, the shortest text that reads back to the same value.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>

#include <cctype>

#include "core/scalar_field.h"
#include "io/readers.h"

namespace cgview::detail {

namespace {

class Out {
 public:
  explicit Out(std::size_t reserve) { s_.reserve(reserve); }
  Out& num(double x) { return put(x); }
  Out& num(float x) { return put(x); }
  Out& num(std::uint64_t x) { return put(x); }
  Out& num(std::uint32_t x) { return put(x); }
  Out& num(int x) { return put(x); }
  Out& str(std::string_view t) {
    s_.append(t);
    return *this;
  }
  Out& ch(char c) {
    s_.push_back(c);
    return *this;
  }
  template <class T>
  Out& raw(T v) {
    if constexpr (std::endian::native == std::endian::big) {
      char b[sizeof(T)];
      std::memcpy(b, &v, sizeof(T));
      std::reverse(b, b + sizeof(T));
      s_.append(b, sizeof(T));
    } else {
      s_.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    return *this;
  }
  std::string take() { return std::move(s_); }

 private:
  template <class T>
  Out& put(T x) {
    char buf[32];
    auto [p, ec] = std::to_chars(buf, buf + sizeof buf, x);
    s_.append(buf, std::size_t(p - buf));
    return *this;
  }
  std::string s_;
};

float unit(std::uint8_t c) { return float(c) / 255.f; }

}  // namespace

std::string write_off(const Mesh& mesh) {
  Out o(mesh.num_vertices() * 40 + mesh.num_faces() * 24 + 64);
  const bool c = mesh.has_colors();
  // OFF readers tell 0..1 float colours from 0..255 integer ones by their
  // values: colours whose components are all 0 or 1 are written as floats, so
  // that they read back as written rather than as white.
  bool unit_floats = c;
  for (const Color& k : mesh.colors) unit_floats &= k.r <= 1 && k.g <= 1 && k.b <= 1;
  o.str(c ? "COFF\n" : "OFF\n")
      .num(std::uint64_t(mesh.num_vertices()))
      .ch(' ')
      .num(std::uint64_t(mesh.num_faces()))
      .str(" 0\n");
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    o.num(p.x).ch(' ').num(p.y).ch(' ').num(p.z);
    if (c) {
      const Color& k = mesh.colors[v];
      if (unit_floats) o.ch(' ').num(unit(k.r)).ch(' ').num(unit(k.g)).ch(' ').num(unit(k.b)).ch(' ').num(unit(k.a));
      else o.ch(' ').num(int(k.r)).ch(' ').num(int(k.g)).ch(' ').num(int(k.b)).ch(' ').num(int(k.a));
    }
    o.ch('\n');
  }
  for (const Tri& t : mesh.faces) o.str("3 ").num(t[0]).ch(' ').num(t[1]).ch(' ').num(t[2]).ch('\n');
  return o.take();
}

std::string write_obj(const Mesh& mesh) {
  Out o(mesh.num_vertices() * 48 + mesh.num_faces() * 40 + 64);
  o.str("# written by CGView\n");
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    o.str("v ").num(p.x).ch(' ').num(p.y).ch(' ').num(p.z);
    if (mesh.has_colors()) {
      const Color& k = mesh.colors[v];
      o.ch(' ').num(unit(k.r)).ch(' ').num(unit(k.g)).ch(' ').num(unit(k.b));
    }
    o.ch('\n');
  }
  for (const Vec2f& t : mesh.uvs) o.str("vt ").num(t.u).ch(' ').num(t.v).ch('\n');
  for (const Vec3f& n : mesh.normals) o.str("vn ").num(n.x).ch(' ').num(n.y).ch(' ').num(n.z).ch('\n');
  const bool t = mesh.has_uvs(), n = mesh.has_normals();
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    o.ch('f');
    for (int k = 0; k < 3; ++k) {
      const Index v = mesh.faces[f][k];
      o.ch(' ').num(v + 1);
      if (t || n) {
        o.ch('/');
        if (t) o.num((mesh.uv_faces.empty() ? v : mesh.uv_faces[f][k]) + 1);
        if (n) o.ch('/').num((mesh.normal_faces.empty() ? v : mesh.normal_faces[f][k]) + 1);
      }
    }
    o.ch('\n');
  }
  return o.take();
}

std::string write_ply(const Mesh& input, bool binary, const ScalarField* field) {
  // A per-vertex field needs the vertices as they are: keep only what is
  // per vertex already (positions, colours) rather than splitting seams.
  Mesh plain;
  if (field) {
    field->check_matches(input);
    plain.positions = input.positions;
    plain.faces = input.faces;
    plain.colors = input.colors;
  }
  const Mesh mesh = field ? std::move(plain) : with_per_vertex_attributes(input);
  const bool vf = field && field->location == Location::vertex, ff = field && field->location == Location::face;
  std::string prop = field ? field->name : "";
  for (char& ch : prop)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') ch = '_';
  if (prop.empty()) prop = "value";
  const bool n = mesh.has_normals(), c = mesh.has_colors(), t = mesh.has_uvs();
  Out o(mesh.num_vertices() * (binary ? 40 : 80) + mesh.num_faces() * (binary ? 13 : 30) + 512);
  o.str("ply\nformat ").str(binary ? "binary_little_endian" : "ascii").str(" 1.0\ncomment written by CGView\n");
  o.str("element vertex ")
      .num(std::uint64_t(mesh.num_vertices()))
      .str("\nproperty float x\nproperty float y\nproperty float z\n");
  if (n) o.str("property float nx\nproperty float ny\nproperty float nz\n");
  if (c) o.str("property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n");
  if (t) o.str("property float s\nproperty float t\n");
  if (vf) o.str("property float ").str(prop).ch('\n');
  // A point cloud's PLY has vertices only, as Open3D and CloudCompare write it.
  if (mesh.num_faces() > 0 || ff)
    o.str("element face ").num(std::uint64_t(mesh.num_faces())).str("\nproperty list uchar int vertex_indices\n");
  if (ff) o.str("property float ").str(prop).ch('\n');
  o.str("end_header\n");
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3f p = to_float(mesh.positions[v]);
    if (binary) {
      o.raw(p.x).raw(p.y).raw(p.z);
      if (n) o.raw(mesh.normals[v].x).raw(mesh.normals[v].y).raw(mesh.normals[v].z);
      if (c) o.raw(mesh.colors[v].r).raw(mesh.colors[v].g).raw(mesh.colors[v].b).raw(mesh.colors[v].a);
      if (t) o.raw(mesh.uvs[v].u).raw(mesh.uvs[v].v);
      if (vf) o.raw(field->values[v]);
    } else {
      o.num(p.x).ch(' ').num(p.y).ch(' ').num(p.z);
      if (n) o.ch(' ').num(mesh.normals[v].x).ch(' ').num(mesh.normals[v].y).ch(' ').num(mesh.normals[v].z);
      if (c)
        o.ch(' ')
            .num(int(mesh.colors[v].r))
            .ch(' ')
            .num(int(mesh.colors[v].g))
            .ch(' ')
            .num(int(mesh.colors[v].b))
            .ch(' ')
            .num(int(mesh.colors[v].a));
      if (t) o.ch(' ').num(mesh.uvs[v].u).ch(' ').num(mesh.uvs[v].v);
      if (vf) o.ch(' ').num(field->values[v]);
      o.ch('\n');
    }
  }
  for (std::size_t i = 0; i < mesh.num_faces(); ++i) {
    const Tri& f = mesh.faces[i];
    if (binary) {
      o.raw(std::uint8_t(3)).raw(std::int32_t(f[0])).raw(std::int32_t(f[1])).raw(std::int32_t(f[2]));
      if (ff) o.raw(field->values[i]);
    } else {
      o.str("3 ").num(f[0]).ch(' ').num(f[1]).ch(' ').num(f[2]);
      if (ff) o.ch(' ').num(field->values[i]);
      o.ch('\n');
    }
  }
  return o.take();
}

std::string write_stl(const Mesh& mesh, bool binary) {
  const std::vector<Vec3> normals = face_normals(mesh);
  if (binary) {
    Out o(84 + 50 * mesh.num_faces());
    std::string header = "binary STL written by CGView";
    header.resize(80, ' ');
    o.str(header).raw(std::uint32_t(mesh.num_faces()));
    for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
      const Vec3f nf = to_float(normals[f]);
      o.raw(nf.x).raw(nf.y).raw(nf.z);
      for (Index v : mesh.faces[f]) {
        const Vec3f p = to_float(mesh.positions[v]);
        o.raw(p.x).raw(p.y).raw(p.z);
      }
      o.raw(std::uint16_t(0));
    }
    return o.take();
  }
  Out o(mesh.num_faces() * 260 + 64);
  o.str("solid cgview\n");
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    const Vec3f nf = to_float(normals[f]);
    o.str("facet normal ").num(nf.x).ch(' ').num(nf.y).ch(' ').num(nf.z).str("\n outer loop\n");
    for (Index v : mesh.faces[f]) {
      const Vec3f p = to_float(mesh.positions[v]);
      o.str("  vertex ").num(p.x).ch(' ').num(p.y).ch(' ').num(p.z).ch('\n');
    }
    o.str(" endloop\nendfacet\n");
  }
  o.str("endsolid cgview\n");
  return o.take();
}

}  // namespace cgview::detail
