#include "io/skeleton_io.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <map>
#include <tuple>

#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "io/text_scanner.h"

namespace cgview {
namespace {

using detail::TextScanner;

constexpr std::uint64_t kMaxSkeletonBytes = 1ull << 30;

bool ends_with(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && std::equal(suffix.rbegin(), suffix.rend(), s.rbegin(),
                                                 [](char a, char b) { return std::tolower(a) == std::tolower(b); });
}

Vec3 need_point(TextScanner& t) {
  const char* at = t.pos();
  Vec3 p;
  p.x = t.need_double("a coordinate");
  p.y = t.need_double("a coordinate");
  p.z = t.need_double("a coordinate");
  if (!is_finite(p)) t.fail_at(at, "a coordinate is not finite");
  return p;
}

// A 1-based index (negative: from the end, as OBJ) into `count` nodes.
Index need_index(TextScanner& t, std::size_t count, bool negative_ok) {
  const char* at = t.pos();
  const std::int64_t i = t.need_int("a node index");
  const std::int64_t resolved = (negative_ok && i < 0) ? std::int64_t(count) + i + 1 : i;
  if (resolved < 1 || resolved > std::int64_t(count))
    t.fail_at(at, "node index " + std::to_string(i) + " is outside 1.." + std::to_string(count));
  return Index(resolved - 1);
}

void add_edge(TextScanner& t, const char* at, Skeleton& s, Index a, Index b) {
  if (a == b) t.fail_at(at, "an edge joins node " + std::to_string(a + 1) + " to itself");
  s.edges.push_back({a, b});
}

Skeleton read_polylines(std::string_view bytes, const std::string& name) {
  TextScanner t(bytes, name);
  Skeleton s;
  std::map<std::tuple<double, double, double>, Index> ids;
  const auto node = [&](Vec3 p) {
    auto [it, fresh] = ids.try_emplace({p.x, p.y, p.z}, Index(s.nodes.size()));
    if (fresh) s.nodes.push_back(p);
    return it->second;
  };
  for (;;) {
    t.skip_space();
    if (t.at_end()) break;
    const char* at = t.pos();
    const std::int64_t n = t.need_int("the number of points of a polyline");
    if (n < 1 || std::uint64_t(n) > t.remaining()) t.fail_at(at, "a polyline of " + std::to_string(n) + " points");
    Index prev = node(need_point(t));
    for (std::int64_t k = 1; k < n; ++k) {
      const char* here = t.pos();
      const Index cur = node(need_point(t));
      if (cur != prev) add_edge(t, here, s, prev, cur);
      prev = cur;
    }
    if (!t.at_eol()) t.fail("more values than the polyline's " + std::to_string(n) + " points: " + t.describe_here());
  }
  return s;
}

Skeleton read_cg_or_obj(std::string_view bytes, const std::string& name, bool obj) {
  TextScanner t(bytes, name);
  Skeleton s;
  for (;;) {
    t.skip_space();
    if (t.at_end()) break;
    const char* at = t.pos();
    const std::string_view w = t.word();
    if (w == "v") {
      s.nodes.push_back(need_point(t));
      if (obj) {  // OBJ allows a w or colour after the point
        while (!t.at_eol()) t.word();
      }
    } else if (w == "e" && !obj) {
      const Index a = need_index(t, s.nodes.size(), false), b = need_index(t, s.nodes.size(), false);
      add_edge(t, at, s, a, b);
    } else if (w == "l" && obj) {
      Index prev = need_index(t, s.nodes.size(), true);
      bool any = false;
      while (!t.at_eol()) {
        std::string_view tok = t.word();
        const std::string_view vertex = tok.substr(0, tok.find('/'));  // "l v/vt"
        TextScanner sub(vertex, name);
        std::int64_t i;
        if (!sub.try_int(i) || !sub.at_end()) t.fail_at(at, "expected a node index, found '" + std::string(tok) + "'");
        const std::int64_t resolved = i < 0 ? std::int64_t(s.nodes.size()) + i + 1 : i;
        if (resolved < 1 || resolved > std::int64_t(s.nodes.size()))
          t.fail_at(at, "node index " + std::to_string(i) + " is outside 1.." + std::to_string(s.nodes.size()));
        add_edge(t, at, s, prev, Index(resolved - 1));
        prev = Index(resolved - 1);
        any = true;
      }
      if (!any) t.fail_at(at, "a line record with one node");
    } else if (obj) {
      t.skip_line();  // faces, normals, groups...: not part of a skeleton
      continue;
    } else {
      t.fail_at(at, "expected 'v' or 'e', found '" + std::string(w.substr(0, 24)) + "'");
    }
    if (!t.at_eol()) t.fail("unexpected " + t.describe_here());
    t.skip_line();
  }
  return s;
}

Skeleton read_json(std::string_view bytes, const std::string& name) {
  nlohmann::json j;
  if (const int depth = json_depth(bytes); depth > kMaxJsonDepth)
    throw ParseError(name,
                     "the JSON nests arrays and objects " + std::to_string(depth) + " deep; at most " +
                         std::to_string(kMaxJsonDepth) + " are read",
                     std::nullopt, std::nullopt);
  try {
    j = nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann counts bytes; the user wants a line.
    const std::size_t at = std::min<std::size_t>(e.byte, bytes.size());
    throw ParseError(name, "not JSON",
                     1 + std::uint64_t(std::count(bytes.begin(), bytes.begin() + std::ptrdiff_t(at), '\n')),
                     std::nullopt);
  } catch (const nlohmann::json::out_of_range&) {
    // A number past a double ("6e8618"): nlohmann throws out_of_range, not
    // a parse_error (found by fuzz_skeleton).
    throw ParseError(name, "a number in the JSON is too large for a double", std::nullopt, std::nullopt);
  }
  const auto bad = [&](const std::string& what) { throw ParseError(name, what, std::nullopt, std::nullopt); };
  if (!j.is_object() || !j.contains("nodes") || !j["nodes"].is_array())
    bad("expected an object with a \"nodes\" array");
  Skeleton s;
  for (const auto& p : j["nodes"]) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
      bad("node " + std::to_string(s.nodes.size()) + " is not [x, y, z]");
    s.nodes.push_back({p[0].get<double>(), p[1].get<double>(), p[2].get<double>()});
  }
  if (j.contains("edges")) {
    if (!j["edges"].is_array()) bad("\"edges\" is not an array");
    for (const auto& e : j["edges"]) {
      if (!e.is_array() || e.size() != 2 || !e[0].is_number_unsigned() || !e[1].is_number_unsigned())
        bad("edge " + std::to_string(s.edges.size()) + " is not [i, j] with two node indices");
      s.edges.push_back({Index(e[0].get<std::uint64_t>()), Index(e[1].get<std::uint64_t>())});
    }
  }
  if (j.contains("radii")) {
    if (!j["radii"].is_array()) bad("\"radii\" is not an array");
    for (const auto& r : j["radii"]) {
      if (!r.is_number()) bad("a radius is not a number");
      s.radii.push_back(r.get<float>());
    }
  }
  return s;
}

void append(std::string& out, double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  out += buf;
}
void append_point(std::string& out, const Vec3& p) {
  append(out, p.x);
  out += ' ';
  append(out, p.y);
  out += ' ';
  append(out, p.z);
}

}  // namespace

SkeletonFormat skeleton_format_from_name(const std::string& name) {
  if (ends_with(name, ".polylines.txt") || ends_with(name, ".polylines")) return SkeletonFormat::polylines;
  if (ends_with(name, ".cg")) return SkeletonFormat::cg;
  if (ends_with(name, ".obj")) return SkeletonFormat::obj;
  if (ends_with(name, ".json")) return SkeletonFormat::json;
  throw UnsupportedFormat("'" + name +
                          "' is not a skeleton file: use .polylines.txt (CGAL), .cg, .obj (l records) or .json");
}

bool is_skeleton_file_name(const std::string& name) {
  try {
    skeleton_format_from_name(name);
    return true;
  } catch (const UnsupportedFormat&) {
    return false;
  }
}

Skeleton read_skeleton_bytes(std::string_view bytes, SkeletonFormat format, const std::string& name) {
  Skeleton s;
  switch (format) {
    case SkeletonFormat::polylines:
      s = read_polylines(bytes, name);
      break;
    case SkeletonFormat::cg:
      s = read_cg_or_obj(bytes, name, false);
      break;
    case SkeletonFormat::obj:
      s = read_cg_or_obj(bytes, name, true);
      break;
    case SkeletonFormat::json:
      s = read_json(bytes, name);
      break;
  }
  if (s.nodes.empty()) throw ParseError(name, "no skeleton node in the file", std::nullopt, std::nullopt);
  try {
    s.validate();
  } catch (const ParseError&) {
    throw;
  } catch (const InvalidInput& e) {
    throw ParseError(name, e.what(), std::nullopt, std::nullopt);
  }
  return s;
}

Skeleton read_skeleton(const std::filesystem::path& path) {
  const SkeletonFormat f = skeleton_format_from_name(path.filename().string());
  return read_skeleton_bytes(read_file_bytes(path, kMaxSkeletonBytes), f, path.filename().string());
}

std::string write_skeleton_bytes(const Skeleton& s, SkeletonFormat format) {
  std::string out;
  switch (format) {
    case SkeletonFormat::polylines:
      // One line per branch (skeleton_branches), as CGAL writes them; a
      // lone node is a polyline of one point.
      for (const std::vector<Index>& b : skeleton_branches(s)) {
        out += std::to_string(b.size());
        for (Index i : b) out += ' ', append_point(out, s.nodes[i]);
        out += '\n';
      }
      {
        const std::vector<std::uint32_t> degree = node_degrees(s);
        for (std::size_t i = 0; i < s.nodes.size(); ++i)
          if (degree[i] == 0) out += "1 ", append_point(out, s.nodes[i]), out += '\n';
      }
      break;
    case SkeletonFormat::cg:
      out = "# D:3 NV:" + std::to_string(s.nodes.size()) + " NE:" + std::to_string(s.edges.size()) + "\n";
      for (const Vec3& p : s.nodes) out += "v ", append_point(out, p), out += '\n';
      for (const auto& e : s.edges) out += "e " + std::to_string(e[0] + 1) + " " + std::to_string(e[1] + 1) + "\n";
      break;
    case SkeletonFormat::obj:
      for (const Vec3& p : s.nodes) out += "v ", append_point(out, p), out += '\n';
      for (const auto& e : s.edges) out += "l " + std::to_string(e[0] + 1) + " " + std::to_string(e[1] + 1) + "\n";
      break;
    case SkeletonFormat::json: {
      nlohmann::json j;
      j["nodes"] = nlohmann::json::array();
      for (const Vec3& p : s.nodes) j["nodes"].push_back({p.x, p.y, p.z});
      j["edges"] = nlohmann::json::array();
      for (const auto& e : s.edges) j["edges"].push_back({e[0], e[1]});
      if (!s.radii.empty()) j["radii"] = s.radii;
      out = j.dump() + "\n";
      break;
    }
  }
  return out;
}

void write_skeleton(const Skeleton& s, const std::filesystem::path& path) {
  write_file_bytes(path, write_skeleton_bytes(s, skeleton_format_from_name(path.filename().string())));
}

}  // namespace cgview
