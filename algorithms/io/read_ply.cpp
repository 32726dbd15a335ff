// PLY (Stanford polygon file), ascii and binary of either byte order: the
// vertex element's x y z, normals (nx ny nz), colours (red green blue
// [alpha], bytes or 0..1 floats, with or without a diffuse_ prefix) and
// texture coordinates (s t, u v, texture_u texture_v); the face element's
// vertex_indices (or vertex_index) list and a per-corner texcoord list, as
// MeshLab writes it; triangle strips (a tristrips element's vertex_indices
// lists, -1 restarting a strip, as Stanford's scans and old tools store
// them).  Other elements and properties are skipped, with a warning.
#include <algorithm>
#include <bit>
#include <initializer_list>
#include <string_view>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "io/readers.h"
#include "io/text_scanner.h"

namespace cgview::detail {

namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

int type_size(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 0;
}

bool parse_type(std::string_view s, Type& t) {
  if (s == "char" || s == "int8") t = Type::i8;
  else if (s == "uchar" || s == "uint8") t = Type::u8;
  else if (s == "short" || s == "int16") t = Type::i16;
  else if (s == "ushort" || s == "uint16") t = Type::u16;
  else if (s == "int" || s == "int32") t = Type::i32;
  else if (s == "uint" || s == "uint32") t = Type::u32;
  else if (s == "float" || s == "float32") t = Type::f32;
  else if (s == "double" || s == "float64") t = Type::f64;
  else return false;
  return true;
}

struct Property {
  std::string name;
  Type type = Type::f32;
  bool is_list = false;
  Type count_type = Type::u8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
};

// A list value as a message shows it: an index read as a double may be 1e75,
// which no integer holds (casting it is undefined: fuzz_ply found it).
std::string index_text(double x) {
  if (std::isfinite(x) && std::fabs(x) < 1e18) return std::to_string(std::int64_t(x));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// The index of the element's first list property of one of these names, or -1.
int list_named(const Element& e, std::initializer_list<std::string_view> names) {
  for (std::size_t i = 0; i < e.props.size(); ++i)
    if (e.props[i].is_list && std::find(names.begin(), names.end(), e.props[i].name) != names.end()) return int(i);
  return -1;
}

enum class Encoding { ascii, little, big };

// Reads binary values, checking the bytes left and swapping as the file says.
class BinaryReader {
 public:
  BinaryReader(const char* p, const char* end, const char* begin, Encoding enc, const std::string& name)
      : p_(p),
        end_(end),
        begin_(begin),
        swap_(enc == Encoding::big ? std::endian::native == std::endian::little
                                   : std::endian::native == std::endian::big),
        name_(name) {}
  double read(Type t) {
    const int n = type_size(t);
    if (end_ - p_ < n) fail("the file ends inside the data (truncated?)");
    unsigned char b[8];
    std::memcpy(b, p_, std::size_t(n));
    if (swap_) std::reverse(b, b + n);
    p_ += n;
    switch (t) {
      case Type::i8:
        return double(static_cast<std::int8_t>(b[0]));
      case Type::u8:
        return double(b[0]);
      case Type::i16: {
        std::int16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case Type::u16: {
        std::uint16_t v;
        std::memcpy(&v, b, 2);
        return v;
      }
      case Type::i32: {
        std::int32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Type::u32: {
        std::uint32_t v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Type::f32: {
        float v;
        std::memcpy(&v, b, 4);
        return v;
      }
      case Type::f64: {
        double v;
        std::memcpy(&v, b, 8);
        return v;
      }
    }
    return 0;
  }
  std::uint64_t offset() const { return std::uint64_t(p_ - begin_); }
  std::uint64_t remaining() const { return std::uint64_t(end_ - p_); }
  const char* pos() const { return p_; }
  void skip(std::uint64_t n) { p_ += n; }
  bool swap() const { return swap_; }
  [[noreturn]] void fail(const std::string& problem) const { throw ParseError(name_, problem, std::nullopt, offset()); }

 private:
  const char* p_;
  const char* end_;
  const char* begin_;
  bool swap_;
  const std::string& name_;
};

// Where each vertex property goes.
enum class Slot { none, x, y, z, nx, ny, nz, r, g, b, a, u, v };

Slot vertex_slot(const std::string& n) {
  if (n == "x") return Slot::x;
  if (n == "y") return Slot::y;
  if (n == "z") return Slot::z;
  if (n == "nx") return Slot::nx;
  if (n == "ny") return Slot::ny;
  if (n == "nz") return Slot::nz;
  if (n == "red" || n == "diffuse_red" || n == "r") return Slot::r;
  if (n == "green" || n == "diffuse_green" || n == "g") return Slot::g;
  if (n == "blue" || n == "diffuse_blue" || n == "b") return Slot::b;
  if (n == "alpha" || n == "diffuse_alpha" || n == "a") return Slot::a;
  if (n == "s" || n == "u" || n == "texture_u" || n == "texture_s") return Slot::u;
  if (n == "t" || n == "v" || n == "texture_v" || n == "texture_t") return Slot::v;
  return Slot::none;
}

std::uint8_t colour_byte(double c, Type t) {
  double v = (t == Type::f32 || t == Type::f64) ? c * 255.0 : c;
  return std::uint8_t(std::clamp(std::lround(v), 0L, 255L));
}

}  // namespace

void read_ply(std::string_view bytes, const std::string& name, ReadResult& result) {
  TextScanner in(bytes, name);
  if (bytes.empty()) in.fail("the file is empty");
  // Any line end: "\n", "\r\n", or the lone "\r" of a file from classic Mac OS.
  if (!bytes.starts_with("ply\n") && !bytes.starts_with("ply\r"))
    in.fail("not a PLY file: it does not start with the line 'ply'");
  in.skip_line();

  // The header.
  Encoding enc = Encoding::ascii;
  bool have_format = false;
  std::vector<Element> elements;
  for (;;) {
    if (in.at_end()) in.fail("the header has no end_header line");
    const char* line = in.pos();
    std::string_view key = in.word();
    if (key == "end_header") {
      in.skip_line();
      break;
    }
    if (key == "format") {
      std::string_view f = in.word();
      if (f == "ascii") enc = Encoding::ascii;
      else if (f == "binary_little_endian") enc = Encoding::little;
      else if (f == "binary_big_endian") enc = Encoding::big;
      else in.fail_at(line, "unknown PLY format '" + std::string(f.substr(0, 32)) + "'");
      have_format = true;
    } else if (key == "element") {
      Element e;
      e.name = std::string(in.word());
      std::int64_t n = in.need_int("an element count");
      if (n < 0) in.fail_at(line, "negative element count");
      e.count = std::uint64_t(n);
      elements.push_back(std::move(e));
    } else if (key == "property") {
      if (elements.empty()) in.fail_at(line, "a property before any element");
      Property p;
      std::string_view t = in.word();
      if (t == "list") {
        p.is_list = true;
        if (!parse_type(in.word(), p.count_type)) in.fail_at(line, "unknown list count type");
        if (!parse_type(in.word(), p.type)) in.fail_at(line, "unknown list item type");
      } else if (!parse_type(t, p.type)) {
        in.fail_at(line, "unknown property type '" + std::string(t.substr(0, 32)) + "'");
      }
      p.name = std::string(in.word());
      if (p.name.empty()) in.fail_at(line, "a property has no name");
      elements.back().props.push_back(std::move(p));
    } else if (key == "comment" || key == "obj_info" || key.empty()) {
    } else {
      in.fail_at(line, "unknown header line '" + std::string(key.substr(0, 32)) + "'");
    }
    in.skip_line();
  }
  if (!have_format) in.fail("the header has no format line");

  Mesh& mesh = result.mesh;
  const char* data = in.pos();
  const std::uint64_t data_bytes = std::uint64_t(bytes.data() + bytes.size() - data);
  const std::uint64_t header_line = in.line_at(data) - 1;

  // Minimal bytes per item of each element, to refuse lying counts up front.
  for (const Element& e : elements) {
    std::uint64_t min_bytes = 0;
    for (const Property& p : e.props)
      min_bytes += enc == Encoding::ascii ? 2 : std::uint64_t(p.is_list ? type_size(p.count_type) : type_size(p.type));
    check_claim(e.count, std::max<std::uint64_t>(min_bytes, enc == Encoding::ascii ? 1 : 0), data_bytes,
                (e.name + " elements").c_str(), name, header_line);
  }

  BinaryReader bin(data, bytes.data() + bytes.size(), bytes.data(), enc, name);
  std::uint64_t polygons = 0, vertex_count = 0;
  bool have_vertices = false, have_faces = false;
  std::vector<double> list;
  std::vector<Index> poly;
  std::vector<Vec2f> wedge_uv;

  auto read_value = [&](Type t) -> double {
    if (enc != Encoding::ascii) return bin.read(t);
    in.skip_space(false);
    const double x = in.need_double("a number");
    // A float property holds a float, as in a binary file ("0.1" is not 0.1f).
    return t == Type::f32 && std::isfinite(x) ? double(float(x)) : x;
  };
  auto read_list = [&](const Property& p, std::vector<double>& out) {
    const double n = read_value(p.count_type);
    if (!(n >= 0) || n != std::floor(n) || std::isinf(n)) {
      if (enc == Encoding::ascii) in.fail("a bad list length");
      bin.fail("a bad list length " + std::to_string(n));
    }
    // Compared as doubles: a length over 2^64 (an ascii "1e30") has no integer.
    const double each = enc == Encoding::ascii ? 2.0 : double(type_size(p.type));
    if (n * each > double(enc == Encoding::ascii ? in.remaining() : bin.remaining())) {
      char count[32];
      std::snprintf(count, sizeof count, n < 1e18 ? "%.0f" : "%g", n);
      if (enc == Encoding::ascii) in.fail("a list claims " + std::string(count) + " items, more than the file holds");
      bin.fail("a list claims " + std::string(count) + " items, more than the file holds");
    }
    out.resize(std::size_t(n));
    for (double& x : out) x = read_value(p.type);
  };
  // One item of an element: its scalars read past, each list read into
  // `list` and given to on_list with its property's index.
  auto read_item = [&](const Element& e, const auto& on_list, const auto& on_scalar) {
    for (std::size_t i = 0; i < e.props.size(); ++i) {
      if (!e.props[i].is_list) {
        on_scalar(i, read_value(e.props[i].type));
        continue;
      }
      read_list(e.props[i], list);
      on_list(i);
    }
  };
  auto fail_here = [&](const std::string& problem) {
    if (enc == Encoding::ascii) in.fail(problem);
    bin.fail(problem);
  };

  for (const Element& e : elements) {
    if (e.name == "vertex" && !have_vertices) {
      have_vertices = true;
      vertex_count = e.count;
      if (e.count > UINT32_MAX - 1) fail_here("over 4 billion vertices");
      std::vector<Slot> slots;
      bool has[13] = {};
      for (const Property& p : e.props) {
        Slot s = p.is_list ? Slot::none : vertex_slot(p.name);
        if (has[int(s)] && s != Slot::none) s = Slot::none;  // first of a name wins
        has[int(s)] = true;
        slots.push_back(s);
      }
      if (!has[int(Slot::x)] || !has[int(Slot::y)] || !has[int(Slot::z)])
        throw ParseError(name, "the vertex element has no x, y and z properties", header_line, std::nullopt);
      // Each other scalar is a field of its own (its index in result.properties).
      std::vector<int> extra(e.props.size(), -1);
      for (std::size_t i = 0; i < e.props.size(); ++i)
        if (!e.props[i].is_list && slots[i] == Slot::none) {
          extra[i] = int(result.properties.size());
          result.properties.push_back({e.props[i].name, Location::vertex, ColorHint::standard, {}});
          result.properties.back().values.resize(e.count);
        }
      const bool has_extra = std::any_of(extra.begin(), extra.end(), [](int k) { return k >= 0; });
      const bool has_n = has[int(Slot::nx)] && has[int(Slot::ny)] && has[int(Slot::nz)];
      const bool has_c = has[int(Slot::r)] && has[int(Slot::g)] && has[int(Slot::b)];
      const bool has_t = has[int(Slot::u)] && has[int(Slot::v)];
      mesh.positions.resize(e.count);
      if (has_n) mesh.normals.resize(e.count);
      if (has_c) mesh.colors.resize(e.count);
      if (has_t) mesh.uvs.resize(e.count);

      // Fast path: binary, no lists, native order, x y z leading as floats.
      bool fixed = enc != Encoding::ascii && !bin.swap();
      std::uint64_t stride = 0;
      for (const Property& p : e.props) {
        fixed &= !p.is_list;
        stride += std::uint64_t(type_size(p.type));
      }
      const bool xyz_float = e.props.size() >= 3 && slots[0] == Slot::x && slots[1] == Slot::y && slots[2] == Slot::z &&
                             e.props[0].type == Type::f32 && e.props[1].type == Type::f32 &&
                             e.props[2].type == Type::f32;
      if (fixed && xyz_float && !has_n && !has_c && !has_t && !has_extra) {
        if (stride * e.count > bin.remaining()) bin.fail("the file ends inside the vertex data (truncated?)");
        const char* base = bin.pos();
        for (std::uint64_t v = 0; v < e.count; ++v) {
          float xyz[3];
          std::memcpy(xyz, base + v * stride, 12);
          mesh.positions[v] = {xyz[0], xyz[1], xyz[2]};
          if (!is_finite(mesh.positions[v]))
            throw ParseError(name, "vertex " + std::to_string(v) + " has a non-finite coordinate", std::nullopt,
                             std::uint64_t(base - bytes.data()) + v * stride);
        }
        bin.skip(stride * e.count);
      } else {
        for (std::uint64_t v = 0; v < e.count; ++v) {
          // Where the vertex starts, for an error message.
          if (enc == Encoding::ascii) in.skip_space(false);
          const char* vertex_pos = enc == Encoding::ascii ? in.pos() : bin.pos();
          for (std::size_t i = 0; i < e.props.size(); ++i) {
            const Property& p = e.props[i];
            if (p.is_list) {
              read_list(p, list);
              continue;
            }
            const double x = read_value(p.type);
            switch (slots[i]) {
              case Slot::x:
                mesh.positions[v].x = x;
                break;
              case Slot::y:
                mesh.positions[v].y = x;
                break;
              case Slot::z:
                mesh.positions[v].z = x;
                break;
              case Slot::nx:
                if (has_n) mesh.normals[v].x = float(x);
                break;
              case Slot::ny:
                if (has_n) mesh.normals[v].y = float(x);
                break;
              case Slot::nz:
                if (has_n) mesh.normals[v].z = float(x);
                break;
              case Slot::r:
                if (has_c) mesh.colors[v].r = colour_byte(x, p.type);
                break;
              case Slot::g:
                if (has_c) mesh.colors[v].g = colour_byte(x, p.type);
                break;
              case Slot::b:
                if (has_c) mesh.colors[v].b = colour_byte(x, p.type);
                break;
              case Slot::a:
                if (has_c) mesh.colors[v].a = colour_byte(x, p.type);
                break;
              case Slot::u:
                if (has_t) mesh.uvs[v].u = float(x);
                break;
              case Slot::v:
                if (has_t) mesh.uvs[v].v = float(x);
                break;
              case Slot::none:
                if (extra[i] >= 0) result.properties[std::size_t(extra[i])].values[v] = float(x);
                break;
            }
          }
          if (!is_finite(mesh.positions[v])) {
            const std::string problem = "vertex " + std::to_string(v) + " has a non-finite coordinate";
            if (enc == Encoding::ascii) in.fail_at(vertex_pos, problem);
            throw ParseError(name, problem, std::nullopt, std::uint64_t(vertex_pos - bytes.data()));
          }
        }
      }
    } else if (e.name == "face" && !have_faces) {
      have_faces = true;
      if (!have_vertices) fail_here("the face element comes before the vertex element");
      const int idx_prop = list_named(e, {"vertex_indices", "vertex_index"}), uv_prop = list_named(e, {"texcoord"});
      if (idx_prop < 0)
        throw ParseError(name, "the face element has no vertex_indices list", header_line, std::nullopt);
      mesh.faces.reserve(std::size_t(std::min<std::uint64_t>(e.count, data_bytes / 4)));
      const bool wedges = uv_prop >= 0 && mesh.uvs.empty();
      bool wedges_ok = wedges;
      // Each scalar of a face is a field, one value per triangle it becomes.
      std::vector<int> extra(e.props.size(), -1);
      for (std::size_t i = 0; i < e.props.size(); ++i)
        if (!e.props[i].is_list) {
          extra[i] = int(result.properties.size());
          result.properties.push_back({e.props[i].name, Location::face, ColorHint::standard, {}});
        }
      std::vector<double> face_values(e.props.size());
      for (std::uint64_t f = 0; f < e.count; ++f) {
        poly.clear();
        wedge_uv.clear();
        read_item(
            e,
            [&](std::size_t i) {
              if (int(i) == idx_prop) {
                for (double x : list) {
                  if (!(x >= 0) || x >= double(vertex_count))
                    fail_here("face " + std::to_string(f) + " refers to vertex " + index_text(x) + " but there are " +
                              std::to_string(vertex_count) + " vertices");
                  poly.push_back(Index(x));
                }
              } else if (int(i) == uv_prop && wedges) {
                for (std::size_t k = 0; k + 1 < list.size(); k += 2)
                  wedge_uv.push_back({float(list[k]), float(list[k + 1])});
              }
            },
            [&](std::size_t i, double x) { face_values[i] = x; });
        if (poly.size() < 3)
          fail_here("face " + std::to_string(f) + " has " + std::to_string(poly.size()) +
                    " corners (at least 3 needed)");
        if (poly.size() > 3) ++polygons;
        if (wedges_ok && wedge_uv.size() != poly.size()) wedges_ok = false;
        for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
          mesh.faces.push_back({poly[0], poly[i], poly[i + 1]});
          for (std::size_t k = 0; k < extra.size(); ++k)
            if (extra[k] >= 0) result.properties[std::size_t(extra[k])].values.push_back(float(face_values[k]));
          if (wedges_ok) {
            const Index base = Index(mesh.uvs.size());
            mesh.uvs.push_back(wedge_uv[0]);
            mesh.uvs.push_back(wedge_uv[i]);
            mesh.uvs.push_back(wedge_uv[i + 1]);
            mesh.uv_faces.push_back({base, base + 1, base + 2});
          }
        }
      }
      if (wedges && !wedges_ok) {
        mesh.uvs.clear();
        mesh.uv_faces.clear();
        result.warnings.push_back("per-corner texture coordinates dropped: their count does not match the corners");
      }
    } else if (e.name == "tristrips") {
      if (!have_vertices) fail_here("the tristrips element comes before the vertex element");
      const int idx_prop = list_named(e, {"vertex_indices", "vertex_index"});
      if (idx_prop < 0)
        throw ParseError(name, "the tristrips element has no vertex_indices list", header_line, std::nullopt);
      std::uint64_t strips = 0, degenerate = 0;
      for (std::uint64_t s = 0; s < e.count; ++s)
        read_item(
            e,
            [&](std::size_t i) {
              if (int(i) != idx_prop) return;
              // Each run between -1s is a strip: corner k makes a triangle with
              // the two before it, every other one turned to keep the strip's
              // orientation; triangles with a repeated corner only join strips.
              poly.clear();
              auto strip_done = [&] {
                for (std::size_t k = 2; k < poly.size(); ++k) {
                  const Index a = poly[k - 2], b = poly[k - 1], c = poly[k];
                  if (a == b || b == c || a == c) {
                    ++degenerate;
                    continue;
                  }
                  mesh.faces.push_back(k % 2 == 0 ? Tri{a, b, c} : Tri{b, a, c});
                }
                strips += poly.size() >= 3;
                poly.clear();
              };
              for (double x : list) {
                if (x == -1) {
                  strip_done();
                  continue;
                }
                if (!(x >= 0) || x >= double(vertex_count))
                  fail_here("strip " + std::to_string(s) + " refers to vertex " + index_text(x) + " but there are " +
                            std::to_string(vertex_count) + " vertices");
                poly.push_back(Index(x));
              }
              strip_done();
            },
            [](std::size_t, double) {});
      have_faces = true;
      result.warnings.push_back("read " + std::to_string(strips) + " triangle strips into triangles" +
                                (degenerate ? " (" + std::to_string(degenerate) +
                                                  " triangles with a repeated corner, which only join strips, left out)"
                                            : std::string()));
    } else {
      // Skip another element (edges, materials, ...) item by item; one
      // without properties has nothing to skip (and its count costs no bytes).
      for (std::uint64_t n = 0; n < e.count && !e.props.empty(); ++n)
        read_item(
            e, [](std::size_t) {}, [](std::size_t, double) {});
      if (e.count) result.warnings.push_back("skipped " + std::to_string(e.count) + " '" + e.name + "' elements");
    }
  }
  if (!have_vertices) throw ParseError(name, "the file has no vertex element", header_line, std::nullopt);
  if (polygons) result.warnings.push_back(std::to_string(polygons) + " polygons were split into triangles");
}

}  // namespace cgview::detail
