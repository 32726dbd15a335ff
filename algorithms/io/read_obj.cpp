// Wavefront OBJ: v (with optional r g b), vt, vn and f records (a line that
// ends with a backslash goes on with the next); polygons are
// fan-triangulated, negative (relative) indices resolved, and every other
// record (o, g, s, usemtl, mtllib, l, p, free-form curves and surfaces)
// skipped, with a warning for each kind that holds geometry.
#include <cmath>

#include "io/readers.h"
#include "io/text_scanner.h"

namespace cgview::detail {

namespace {
constexpr Index kNone = UINT32_MAX;

// Resolves a 1-based (or negative, relative) OBJ index against a count.
Index resolve(std::int64_t i, std::size_t count, TextScanner& in, const char* what, std::size_t face) {
  std::int64_t r = i > 0 ? i - 1 : std::int64_t(count) + i;
  if (i == 0 || r < 0 || r >= std::int64_t(count))
    in.fail("face " + std::to_string(face) + " refers to " + what + " " + std::to_string(i) + " but " +
            std::to_string(count) + " are defined before it");
  return Index(r);
}
}  // namespace

void read_obj(std::string_view bytes, const std::string& name, ReadResult& result) {
  std::string joined;
  TextScanner in(join_continued_lines(bytes, joined), name);
  Mesh& mesh = result.mesh;
  std::vector<Vec3f> colours;  // "v x y z r g b" (0..1), an extension MeshLab writes
  std::vector<Vec2f> uvs;
  std::vector<Vec3f> normals;
  std::vector<Tri> uv_faces, normal_faces;
  bool any_uv = false, any_no_uv = false, any_n = false, any_no_n = false;
  std::uint64_t polygons = 0, skipped_lines = 0, skipped_points = 0, unknown_records = 0, freeform = 0;
  std::size_t colour_count = 0;

  struct Corner {
    Index v, t, n;
  };
  std::vector<Corner> poly;
  bool saw_any = false;
  while (!in.at_end()) {
    in.skip_blanks();
    const char* line_start = in.pos();
    if (in.at_end()) break;
    if (in.at_eol()) {
      in.skip_line();
      continue;
    }
    std::string_view key = in.word();
    if (key == "v") {
      saw_any = true;
      Vec3 p;
      for (int i = 0; i < 3; ++i) p[i] = in.need_double("a vertex coordinate");
      if (!is_finite(p))
        in.fail_at(line_start, "vertex " + std::to_string(mesh.positions.size() + 1) + " has a non-finite coordinate");
      if (!in.at_eol()) {
        double r, g, b;
        if (in.try_double(r) && in.try_double(g) && in.try_double(b)) {
          if (colours.size() < mesh.positions.size()) colours.resize(mesh.positions.size());
          colours.push_back({float(r), float(g), float(b)});
          ++colour_count;
        } else if (!in.at_eol()) {
          double w;  // a homogeneous w: "v x y z w"
          in.set_pos(line_start + 1);
          for (int i = 0; i < 3; ++i) in.need_double("a vertex coordinate");
          if (!in.try_double(w) || !in.at_eol()) in.fail("unexpected " + in.describe_here() + " in a vertex record");
        }
      }
      mesh.positions.push_back(p);
      in.skip_line();
    } else if (key == "vt") {
      Vec2f t;
      t.u = float(in.need_double("a texture coordinate"));
      double v = 0;
      if (!in.at_eol()) v = in.need_double("a texture coordinate");
      t.v = float(v);
      uvs.push_back(t);
      in.skip_line();
    } else if (key == "vn") {
      Vec3f n;
      for (int i = 0; i < 3; ++i) n[i] = float(in.need_double("a normal coordinate"));
      normals.push_back(n);
      in.skip_line();
    } else if (key == "f" || key == "fo") {
      saw_any = true;
      const std::size_t face = mesh.faces.size();
      poly.clear();
      while (!in.at_eol()) {
        Corner c{kNone, kNone, kNone};
        std::int64_t i;
        if (!in.try_int(i)) {
          // "a/b/c": parse piecewise without the whole-token check.
          const char* s = in.pos();
          const char* e = s;
          while (e < in.end() && !TextScanner::is_space(*e) && *e != '#') ++e;
          std::string_view tok(s, std::size_t(e - s));
          std::int64_t part[3] = {0, 0, 0};
          bool present[3] = {false, false, false};
          std::size_t field = 0, pos = 0;
          while (pos <= tok.size() && field < 3) {
            std::size_t slash = tok.find('/', pos);
            std::string_view piece =
                tok.substr(pos, slash == std::string_view::npos ? std::string_view::npos : slash - pos);
            if (!piece.empty()) {
              auto [ptr, ec] = std::from_chars(piece.data(), piece.data() + piece.size(), part[field]);
              if (ec != std::errc() || ptr != piece.data() + piece.size())
                in.fail("expected a face corner like 3, 3/1, 3//2 or 3/1/2, found " + in.describe_here());
              present[field] = true;
            }
            ++field;
            if (slash == std::string_view::npos) break;
            pos = slash + 1;
            if (field == 3) in.fail("a face corner has more than three parts: " + in.describe_here());
          }
          if (!present[0]) in.fail("a face corner has no vertex index: " + in.describe_here());
          c.v = resolve(part[0], mesh.positions.size(), in, "vertex", face);
          if (present[1]) c.t = resolve(part[1], uvs.size(), in, "texture coordinate", face);
          if (present[2]) c.n = resolve(part[2], normals.size(), in, "normal", face);
          in.set_pos(e);
        } else {
          c.v = resolve(i, mesh.positions.size(), in, "vertex", face);
        }
        poly.push_back(c);
      }
      if (poly.size() < 3)
        in.fail_at(line_start, "a face has " + std::to_string(poly.size()) + " corners (at least 3 needed)");
      if (poly.size() > 3) ++polygons;
      for (std::size_t i = 1; i + 1 < poly.size(); ++i) {
        const Corner& a = poly[0];
        const Corner& b = poly[i];
        const Corner& c = poly[i + 1];
        mesh.faces.push_back({a.v, b.v, c.v});
        const bool has_t = a.t != kNone && b.t != kNone && c.t != kNone;
        const bool has_n = a.n != kNone && b.n != kNone && c.n != kNone;
        (has_t ? any_uv : any_no_uv) = true;
        (has_n ? any_n : any_no_n) = true;
        uv_faces.push_back({a.t, b.t, c.t});
        normal_faces.push_back({a.n, b.n, c.n});
      }
      in.skip_line();
    } else if (key == "l") {
      ++skipped_lines;
      in.skip_line();
    } else if (key == "p") {
      ++skipped_points;
      in.skip_line();
    } else if (key == "o" || key == "g" || key == "s" || key == "usemtl" || key == "mtllib" || key == "mg" ||
               key == "lod" || key == "bevel" || key == "c_interp" || key == "d_interp" || key == "shadow_obj" ||
               key == "trace_obj") {
      in.skip_line();  // grouping and display: the geometry is all read
    } else if (key == "vp" || key == "cstype" || key == "deg" || key == "bmat" || key == "step" || key == "curv" ||
               key == "curv2" || key == "surf" || key == "parm" || key == "trim" || key == "hole" || key == "scrv" ||
               key == "sp" || key == "end" || key == "con" || key == "ctech" || key == "stech") {
      ++freeform;  // curves and surfaces: geometry that is not read
      in.skip_line();
    } else {
      for (char ch : key)
        if (static_cast<unsigned char>(ch) < 32 || static_cast<unsigned char>(ch) > 126)
          in.fail_at(line_start, "not a text OBJ file: binary data where a record should start");
      ++unknown_records;
      in.skip_line();
    }
  }
  if (!saw_any) throw ParseError(name, "the file has no vertices and no faces", std::nullopt, std::nullopt);

  // Attributes are kept when every face has them; a mix is dropped with a word.
  if (any_uv && !any_no_uv) {
    mesh.uvs = std::move(uvs);
    mesh.uv_faces = std::move(uv_faces);
  } else if (any_uv) {
    result.warnings.push_back("texture coordinates dropped: some faces have them and others do not");
  }
  if (any_n && !any_no_n) {
    mesh.normals = std::move(normals);
    mesh.normal_faces = std::move(normal_faces);
  } else if (any_n) {
    result.warnings.push_back("normals dropped: some faces have them and others do not");
  }
  // A point cloud's OBJ (no faces) pairs its normals with its vertices in order.
  if (mesh.faces.empty() && !normals.empty()) {
    if (normals.size() == mesh.positions.size()) mesh.normals = std::move(normals);
    else result.warnings.push_back("normals dropped: a file of points has them, but not one per vertex");
  }
  // Indices that coincide with the vertex indices become per-vertex attributes.
  auto collapse = [&](std::vector<Tri>& idx, auto& values) {
    if (idx.empty() || values.size() != mesh.positions.size()) return;
    for (std::size_t f = 0; f < idx.size(); ++f)
      if (idx[f] != mesh.faces[f]) return;
    idx.clear();
  };
  collapse(mesh.uv_faces, mesh.uvs);
  collapse(mesh.normal_faces, mesh.normals);

  if (colour_count) {
    if (colour_count != mesh.positions.size()) {
      result.warnings.push_back("vertex colours dropped: only some vertices have them");
    } else {
      mesh.colors.resize(colours.size());
      for (std::size_t v = 0; v < colours.size(); ++v) {
        auto byte = [](float x) { return std::uint8_t(std::clamp(std::lround(x * 255.f), 0L, 255L)); };
        mesh.colors[v] = {byte(colours[v].x), byte(colours[v].y), byte(colours[v].z), 255};
      }
    }
  }
  if (polygons) result.warnings.push_back(std::to_string(polygons) + " polygons were split into triangles");
  if (skipped_lines) result.warnings.push_back(std::to_string(skipped_lines) + " line records (l) were skipped");
  if (unknown_records)
    result.warnings.push_back(std::to_string(unknown_records) + " records of unknown kinds were skipped");
  if (skipped_points) result.warnings.push_back(std::to_string(skipped_points) + " point records (p) were skipped");
  if (freeform)
    result.warnings.push_back(
        std::to_string(freeform) +
        " free-form curve and surface records (vp, curv, surf, ...) were skipped: only polygons are read");
}

}  // namespace cgview::detail
