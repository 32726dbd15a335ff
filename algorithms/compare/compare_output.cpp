#include "compare/compare_output.h"

// The kernel first: distance.h calls CGAL::midpoint without including it.
#include "core/surface_mesh.h"

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "skeleton/skeleton_distance.h"

namespace cgview {
namespace {

constexpr double kTiny = 1e-12;

// The methods of a kind with their default tolerances, the default first;
// none for a kind that cannot be compared.
std::vector<std::pair<std::string, double>> methods_of(OutputKind kind) {
  switch (kind) {
    case OutputKind::scalar_field:
      return {{"relative", 0.03}, {"correlation", 0.95}};
    case OutputKind::mesh:
    case OutputKind::skeleton:
      return {{"hausdorff", 0.01}};
    case OutputKind::metrics:
      return {{"tolerance", 0.01}};
    default:
      return {};
  }
}

// "a scalar field", "an animation", "a metrics table": for messages.
std::string noun(OutputKind kind) {
  if (kind == OutputKind::metrics) return "a metrics table";
  std::string k = to_string(kind);
  std::replace(k.begin(), k.end(), '_', ' ');
  return (k[0] == 'a' ? "an " : "a ") + k;
}

std::string number(double v, int digits) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// Throws InvalidInput unless spec fits an output of `kind`.
void check_spec(const CompareSpec& spec, OutputKind kind) {
  const auto methods = methods_of(kind);
  if (methods.empty())
    throw InvalidInput("compare spec: " + noun(kind) + " cannot be compared (a scalar field, a mesh, a skeleton or " +
                       "a metrics table can)");
  std::string names;
  for (const auto& [name, tolerance] : methods) names += (names.empty() ? "" : ", ") + name;
  if (std::none_of(methods.begin(), methods.end(), [&](const auto& m) { return m.first == spec.method; }))
    throw InvalidInput("compare spec: method '" + spec.method + "' is not one for " + noun(kind) + " (" + names + ")");
  if (spec.method == "correlation") {
    if (!(spec.tolerance >= -1 && spec.tolerance <= 1))
      throw InvalidInput("compare spec: a correlation tolerance is between -1 and 1, not " + number(spec.tolerance, 6));
  } else if (!(spec.tolerance >= 0)) {
    throw InvalidInput("compare spec: tolerance " + number(spec.tolerance, 6) + " is negative");
  }
  if (!spec.keys.empty() && kind != OutputKind::metrics)
    throw InvalidInput("compare spec: keys are for a metrics table, not " + noun(kind));
  for (const auto& [key, tolerance] : spec.keys)
    if (!(tolerance >= 0)) throw InvalidInput("compare spec: key '" + key + "' has a negative tolerance");
}

// a and b in `digits` significant digits, more where they would read the
// same but differ (3.0004% over the 3% allowed must not read "3% over 3%").
std::pair<std::string, std::string> numbers(double a, double b, int digits) {
  while (a != b && digits < 12 && number(a, digits) == number(b, digits)) ++digits;
  return {number(a, digits), number(b, digits)};
}

Verdict fail(std::string reason, std::map<std::string, double> measures = {}) {
  return {false, std::move(reason), std::move(measures)};
}

// measured against allowed, in `unit`: "mean error 12% of the range over the
// 3% allowed", "correlation 0.81 under the 0.95 required".
Verdict judge(bool pass, double measured, double allowed, const std::string& what, const std::string& unit,
              const std::string& of, const std::string& over, const std::string& word,
              std::map<std::string, double> measures) {
  const auto [m, a] = numbers(measured, allowed, 3);
  if (pass)
    return {true, "within tolerance: " + what + " " + m + unit + of + " (" + a + unit + " " + word + ")", measures};
  return fail(what + " " + m + unit + of + " " + over + " the " + a + unit + " " + word, std::move(measures));
}

Verdict compare_fields(const ScalarField& r, const ScalarField& s, const CompareSpec& spec) {
  if (r.location != s.location)
    return fail(std::string("a per-") + to_string(r.location) + " field where a per-" + to_string(s.location) +
                " field was expected");
  if (r.values.size() != s.values.size())
    return fail("a field of " + std::to_string(r.values.size()) + " values where the reference has " +
                std::to_string(s.values.size()));
  // Where the reference has no number (an unreachable vertex's distance)
  // there is nothing to match.
  std::vector<std::size_t> at;
  std::size_t not_numbers = 0;
  for (std::size_t i = 0; i < s.values.size(); ++i)
    if (std::isfinite(s.values[i])) {
      at.push_back(i);
      not_numbers += !std::isfinite(r.values[i]);
    }
  if (at.empty()) throw InvalidInput("the reference field has no finite value to compare with");
  if (not_numbers)
    return fail(std::to_string(not_numbers) + " of " + std::to_string(at.size()) + " values are not numbers");

  if (spec.method == "relative") {
    const auto [lo, hi] = s.range();
    double scale = double(hi) - double(lo);
    if (scale == 0)
      for (std::size_t i : at) scale = std::max({scale, std::abs(double(s.values[i])), kTiny});
    double sum = 0, largest = 0;
    for (std::size_t i : at) {
      const double e = std::abs(double(r.values[i]) - double(s.values[i])) / scale;
      sum += e;
      largest = std::max(largest, e);
    }
    const double mean = sum / double(at.size());
    const std::string of = hi > lo ? " of the range" : " of the reference's magnitude";
    return judge(mean <= spec.tolerance, 100 * mean, 100 * spec.tolerance, "mean error", "%", of, "over", "allowed",
                 {{"mean_error", mean}, {"max_error", largest}, {"scale", scale}});
  }

  // Pearson's correlation, undefined for a constant field: tested first, by
  // the values themselves (a computed variance of a constant need not be 0).
  const auto constant = [&](const ScalarField& f) {
    return std::all_of(at.begin(), at.end(), [&](std::size_t i) { return f.values[i] == f.values[at[0]]; });
  };
  const bool r_flat = constant(r), s_flat = constant(s);
  if (r_flat && s_flat) return {true, "within tolerance: both fields are constant", {{"correlation", 1.0}}};
  if (s_flat) return fail("the field varies where the reference is constant: no correlation to measure");
  if (r_flat) return fail("a constant field where the reference varies: no correlation to measure");
  double mr = 0, ms = 0;
  for (std::size_t i : at) mr += r.values[i], ms += s.values[i];
  mr /= double(at.size());
  ms /= double(at.size());
  double rs = 0, rr = 0, ss = 0;
  for (std::size_t i : at) {
    const double dr = r.values[i] - mr, ds = s.values[i] - ms;
    rs += dr * ds, rr += dr * dr, ss += ds * ds;
  }
  const double c = std::clamp(rs / std::sqrt(rr * ss), -1.0, 1.0);
  return judge(c >= spec.tolerance, c, spec.tolerance, "correlation", "", "", "under", "required",
               {{"correlation", c}});
}

// The mesh's faces in a halfedge structure, whole: a face that does not fit
// (at a non-manifold edge or vertex: a voxel surface, whose cubes meet at
// edges) gets copies of its corners of its own, where to_surface_mesh would
// leave it out.  Faces with a repeated corner have no area and stay out, and
// so do vertices of no face, which CGAL would sample as points.
SurfaceMesh whole_surface(const Mesh& m) {
  SurfaceMesh sm;
  std::vector<SurfaceMesh::Vertex_index> shared(m.num_vertices(), SurfaceMesh::null_vertex());
  const auto point = [&](Index v) { return Point3(m.positions[v].x, m.positions[v].y, m.positions[v].z); };
  for (const Tri& f : m.faces) {
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) continue;
    std::array<SurfaceMesh::Vertex_index, 3> v;
    for (int k = 0; k < 3; ++k) {
      if (shared[f[k]] == SurfaceMesh::null_vertex()) shared[f[k]] = sm.add_vertex(point(f[k]));
      v[k] = shared[f[k]];
    }
    if (sm.add_face(v[0], v[1], v[2]) != SurfaceMesh::null_face()) continue;
    for (int k = 0; k < 3; ++k) v[k] = sm.add_vertex(point(f[k]));
    sm.add_face(v[0], v[1], v[2]);
  }
  return sm;
}

// The grid spacing of CGAL's sampling of `sm`: `spacing`, made coarser until
// the samples it adds to the corners (as sample_triangles places them: n =
// ceil(longest edge / spacing) per face gives (n-1)(n-2)/2 inner points, and
// ceil(edge / spacing) - 1 along each edge) are at most kMaxSamples, so that
// a huge or sliver-filled mesh costs bounded time and memory.  The corners,
// three a face, are as many as the mesh is large whatever the spacing.
double bounded_spacing(const SurfaceMesh& sm, double spacing) {
  constexpr double kMaxSamples = 400'000;
  std::vector<std::array<double, 3>> edges;
  edges.reserve(sm.number_of_faces());
  for (auto f : sm.faces()) {
    std::array<double, 3> e{};
    auto h = sm.halfedge(f);
    for (double& l : e) {
      l = std::sqrt(CGAL::to_double(CGAL::squared_distance(sm.point(sm.source(h)), sm.point(sm.target(h)))));
      h = sm.next(h);
    }
    edges.push_back(e);
  }
  for (;;) {
    double count = 0;
    for (const auto& e : edges) {
      const double n = std::ceil(std::max({e[0], e[1], e[2]}) / spacing);
      count += std::max(0.0, (n - 1) * (n - 2) / 2);
      for (double l : e) count += std::max(0.0, std::ceil(l / spacing) - 1);
    }
    if (count <= kMaxSamples) return spacing;
    spacing *= std::max(1.1, std::sqrt(count / kMaxSamples));
  }
}

Verdict compare_meshes(const Mesh& r, const Mesh& s, const CompareSpec& spec) {
  try {
    r.validate();
  } catch (const InvalidInput& e) {
    return fail(std::string("an invalid mesh: ") + e.what());
  }
  s.validate();
  const SurfaceMesh a = whole_surface(r), b = whole_surface(s);
  if (b.number_of_faces() == 0) throw InvalidInput("the reference mesh has no faces to compare with");
  if (a.number_of_faces() == 0) return fail("a mesh with no faces");
  const double diagonal = bounding_box(s).diagonal();
  if (!(diagonal > 0)) throw InvalidInput("the reference mesh has an empty bounding box");

  // A grid of 1/250 of the diagonal: samples at most 0.4% of it from any
  // point, so a distance is found within that, the same on every call
  // (random sampling would not be).
  namespace PMP = CGAL::Polygon_mesh_processing;
  const double spacing = diagonal / 250;
  const auto grid = [](double d) { return CGAL::parameters::use_grid_sampling(true).grid_spacing(d); };
  const double h = PMP::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      a, b, grid(bounded_spacing(a, spacing)), grid(bounded_spacing(b, spacing)));
  const double relative = h / diagonal;
  return judge(relative <= spec.tolerance, 100 * relative, 100 * spec.tolerance, "Hausdorff distance", "%",
               " of the diagonal", "over", "allowed", {{"hausdorff", relative}, {"diagonal", diagonal}});
}

Verdict compare_skeletons(const Skeleton& r, const Skeleton& s, const CompareSpec& spec) {
  try {
    r.validate();
  } catch (const InvalidInput& e) {
    return fail(std::string("an invalid skeleton: ") + e.what());
  }
  s.validate();
  if (s.nodes.empty()) throw InvalidInput("the reference skeleton has no nodes to compare with");
  if (r.nodes.empty()) return fail("a skeleton with no nodes");
  const double diagonal = bounding_box(s).diagonal();
  if (!(diagonal > 0)) throw InvalidInput("the reference skeleton has an empty bounding box");
  // skeleton_distance's own spacing, 1/500 of both skeletons' box: at most
  // 500 samples an edge however far a result strays.
  const Metrics d = skeleton_distance(r, s).metrics;
  const double relative = d.at("hausdorff") / diagonal;
  return judge(relative <= spec.tolerance, 100 * relative, 100 * spec.tolerance, "Hausdorff distance", "%",
               " of the diagonal", "over", "allowed",
               {{"hausdorff", relative}, {"mean", d.at("mean") / diagonal}, {"diagonal", diagonal}});
}

Verdict compare_metrics(const Metrics& r, const Metrics& s, const CompareSpec& spec) {
  std::map<std::string, double> tolerances = spec.keys;
  if (tolerances.empty())
    for (const auto& [key, value] : s) tolerances[key] = spec.tolerance;
  if (tolerances.empty()) throw InvalidInput("the reference has no metrics to compare with");
  Verdict v{true, "", {}};
  std::vector<std::string> wrong;
  for (const auto& [key, tolerance] : tolerances) {
    const auto sk = s.find(key);
    if (sk == s.end()) throw InvalidInput("compare spec: metric '" + key + "' is not in the reference");
    if (!std::isfinite(sk->second)) throw InvalidInput("the reference's metric '" + key + "' is not a number");
    const auto rk = r.find(key);
    if (rk == r.end()) {
      wrong.push_back("missing metric '" + key + "'");
      continue;
    }
    const double scale = std::max(std::abs(sk->second), kTiny), error = std::abs(rk->second - sk->second) / scale;
    v.measures[key] = error;
    if (!(error <= tolerance)) {  // NaN fails too
      const auto [got, want] = numbers(rk->second, sk->second, 6);
      wrong.push_back("metric '" + key + "' is " + got + " where the reference has " + want + " (" +
                      number(100 * tolerance, 3) + "% allowed)");
    }
  }
  for (const std::string& w : wrong) v.reason += (v.reason.empty() ? "" : "; ") + w;
  v.pass = wrong.empty();
  if (v.pass)
    v.reason =
        "within tolerance: " + std::to_string(tolerances.size()) + " metric" + (tolerances.size() == 1 ? "" : "s");
  return v;
}

}  // namespace

CompareSpec compare_spec_from_json(const nlohmann::json& j, OutputKind kind) {
  if (!j.is_null() && !j.is_object()) throw InvalidInput("compare spec: an object {method, tolerance, keys}");
  for (const auto& [field, value] : j.items())
    if (field != "method" && field != "tolerance" && field != "keys")
      throw InvalidInput("compare spec: unknown field '" + field + "' (method, tolerance, keys)");
  const auto given = [&](const char* field) { return j.is_object() && j.contains(field) && !j[field].is_null(); };
  const auto methods = methods_of(kind);
  CompareSpec spec;
  if (given("method")) {
    if (!j["method"].is_string()) throw InvalidInput("compare spec: method is a string");
    spec.method = j["method"].get<std::string>();
  } else if (!methods.empty()) {
    spec.method = methods.front().first;
  }
  if (given("tolerance")) {
    if (!j["tolerance"].is_number()) throw InvalidInput("compare spec: tolerance is a number");
    spec.tolerance = j["tolerance"].get<double>();
  } else {
    for (const auto& [name, tolerance] : methods)
      if (name == spec.method) spec.tolerance = tolerance;
  }
  if (given("keys")) {
    if (!j["keys"].is_object()) throw InvalidInput("compare spec: keys is an object of key: tolerance");
    for (const auto& [key, value] : j["keys"].items()) {
      if (!value.is_number()) throw InvalidInput("compare spec: the tolerance of key '" + key + "' is a number");
      spec.keys[key] = value.get<double>();
    }
  }
  check_spec(spec, kind);
  return spec;
}

nlohmann::json to_json(const CompareSpec& spec) {
  nlohmann::json j = {{"method", spec.method}, {"tolerance", spec.tolerance}};
  if (!spec.keys.empty()) j["keys"] = spec.keys;
  return j;
}

Verdict compare_output(const ArtifactValue& result, const ArtifactValue& reference, const CompareSpec& spec) {
  const OutputKind kind = kind_of(reference);
  check_spec(spec, kind);
  if (kind_of(result) != kind) return fail(noun(kind_of(result)) + " where " + noun(kind) + " was expected");
  switch (kind) {
    case OutputKind::scalar_field:
      return compare_fields(std::get<ScalarField>(result), std::get<ScalarField>(reference), spec);
    case OutputKind::mesh:
      return compare_meshes(std::get<Mesh>(result), std::get<Mesh>(reference), spec);
    case OutputKind::skeleton:
      return compare_skeletons(std::get<Skeleton>(result), std::get<Skeleton>(reference), spec);
    default:  // check_spec let only metrics through
      return compare_metrics(std::get<Metrics>(result), std::get<Metrics>(reference), spec);
  }
}

}  // namespace cgview
