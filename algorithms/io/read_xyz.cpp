// Point clouds as text rows, one point a line: XYZ (`x y z [nx ny nz]`, as
// Open3D, MeshLab and CloudCompare write it) and Leica's PTS (a count line,
// then `x y z [intensity [r g b]]`; a file may hold several scans, each
// with its count).  Both are read as a mesh with no faces
// (core/point_cloud.h); XYZ is written too.
#include <charconv>

#include "io/readers.h"
#include "io/text_scanner.h"

namespace cgview::detail {

namespace {

// The numbers of the current line (at most `most`), leaving the cursor at
// its end; throws naming the line when a word is not a number.
int row(TextScanner& in, double* out, int most) {
  int n = 0;
  while (!in.at_eol()) {
    if (n == most) in.fail("more than " + std::to_string(most) + " numbers on a line");
    out[n++] = in.need_double("a number");
  }
  return n;
}

Vec3 point_of(TextScanner& in, const double* v, std::size_t index) {
  const Vec3 p{v[0], v[1], v[2]};
  if (!is_finite(p)) in.fail("point " + std::to_string(index) + " has a non-finite coordinate");
  return p;
}

std::uint8_t colour_byte(TextScanner& in, double c) {
  if (!(c >= 0 && c <= 255)) in.fail("a colour of " + std::to_string(c) + ", outside 0..255");
  return std::uint8_t(std::lround(c));
}

}  // namespace

void read_xyz(std::string_view bytes, const std::string& name, ReadResult& result) {
  TextScanner in(bytes, name);
  Mesh& mesh = result.mesh;
  int columns = 0;  // 3 or 6, set by the first row and then held
  for (in.skip_space(); !in.at_end(); in.skip_space()) {
    double v[6];
    const int n = row(in, v, 6);
    if (n != 3 && n != 6) in.fail("a row of " + std::to_string(n) + " numbers: XYZ has x y z [nx ny nz]");
    if (columns == 0) columns = n;
    if (n != columns) in.fail("a row of " + std::to_string(n) + " numbers after rows of " + std::to_string(columns));
    mesh.positions.push_back(point_of(in, v, mesh.positions.size()));
    if (n == 6) mesh.normals.push_back({float(v[3]), float(v[4]), float(v[5])});
  }
  if (mesh.positions.empty()) in.fail("the file has no points");
}

void read_pts(std::string_view bytes, const std::string& name, ReadResult& result) {
  TextScanner in(bytes, name);
  Mesh& mesh = result.mesh;
  int columns = 0;  // 3, 4, 6 or 7, set by the first row and then held
  for (in.skip_space(); !in.at_end(); in.skip_space()) {
    const char* count_at = in.pos();
    const std::int64_t count = in.need_int("the number of points");
    if (count < 0 || count > std::int64_t(UINT32_MAX) - 1) in.fail_at(count_at, "a point count out of range");
    if (!in.at_eol()) in.fail("expected the number of points alone on its line, found " + in.describe_here());
    // A point needs at least "0 0 0\n".
    check_claim(std::uint64_t(count), 6, in.remaining(), "points", name, in.line_at(count_at));
    mesh.positions.reserve(mesh.positions.size() + std::size_t(count));
    for (std::int64_t i = 0; i < count; ++i) {
      in.skip_space();
      if (in.at_end())
        in.fail("the file ends after " + std::to_string(i) + " of its " + std::to_string(count) + " points");
      double v[7];
      const int n = row(in, v, 7);
      if (n != 3 && n != 4 && n != 6 && n != 7)
        in.fail("a row of " + std::to_string(n) + " numbers: PTS has x y z [intensity] [r g b]");
      if (columns == 0) columns = n;
      if (n != columns) in.fail("a row of " + std::to_string(n) + " numbers after rows of " + std::to_string(columns));
      mesh.positions.push_back(point_of(in, v, mesh.positions.size()));
      if (n >= 6) {
        const double* c = v + n - 3;
        mesh.colors.push_back({colour_byte(in, c[0]), colour_byte(in, c[1]), colour_byte(in, c[2]), 255});
      }
    }
  }
  if (mesh.positions.empty()) in.fail("the file has no points");
  if (columns == 4 || columns == 7) result.warnings.push_back(name + ": the scanner's intensities are not kept");
}

std::string write_xyz(const Mesh& mesh) {
  const bool n = mesh.has_normals() && mesh.normal_faces.empty();
  std::string out;
  out.reserve(mesh.num_vertices() * (n ? 72 : 40));
  char buf[32];
  auto num = [&](auto x, char after) {
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    out.append(buf, std::size_t(r.ptr - buf));
    out += after;
  };
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    const Vec3& p = mesh.positions[v];
    num(p.x, ' ');
    num(p.y, ' ');
    num(p.z, n ? ' ' : '\n');
    if (n) {
      num(mesh.normals[v].x, ' ');
      num(mesh.normals[v].y, ' ');
      num(mesh.normals[v].z, '\n');
    }
  }
  return out;
}

}  // namespace cgview::detail
