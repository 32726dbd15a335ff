// CGAL_EIGEN3_ENABLED is set by CMake (algorithms/CMakeLists.txt): the heat method solves
// two sparse systems with Eigen.
#include "filters/geodesic_distance.h"

#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

namespace cgview {
namespace {

std::vector<std::size_t> parse_sources(const std::string& text, std::size_t num_vertices) {
  std::vector<std::size_t> out;
  std::string_view rest = text;
  while (true) {
    const std::size_t comma = rest.find(',');
    std::string_view item = rest.substr(0, comma);
    while (!item.empty() && (item.front() == ' ' || item.front() == '\t')) item.remove_prefix(1);
    while (!item.empty() && (item.back() == ' ' || item.back() == '\t')) item.remove_suffix(1);
    unsigned long long v = 0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || ec != std::errc() || ptr != item.data() + item.size())
      throw InvalidInput("parameter 'sources': '" + std::string(item) +
                         "' is not a vertex index (expected comma-separated indices such as \"0,12\")");
    if (v >= num_vertices)
      throw InvalidInput("parameter 'sources': vertex " + std::to_string(v) + " is out of range (the mesh has " +
                         std::to_string(num_vertices) + " vertices)");
    out.push_back(std::size_t(v));
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  return out;
}

}  // namespace

GeodesicDistanceResult geodesic_distance(const Mesh& mesh, const GeodesicDistanceParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("geodesic_distance needs a mesh with faces");
  const std::vector<std::size_t> sources = parse_sources(p.sources, mesh.num_vertices());
  ctx.progress(0, "converting");
  GeodesicDistanceResult result;
  bool repaired = false;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "geodesic_distance", p.repair, result.warnings, &repaired);
  using Vertex = SurfaceMesh::Vertex_index;
  // Vertex i of the mesh is vertex i of sm, unless repaired: then the
  // copy's vertices at its position (several where a non-manifold vertex
  // was split, none where an isolated one was removed).
  std::vector<std::vector<Vertex>> copies;
  if (repaired) copies = vertices_after_repair(mesh, sm);
  auto copies_of = [&](std::size_t i) {
    std::vector<Vertex> out;
    if (!repaired) out.push_back(Vertex(SurfaceMesh::size_type(i)));
    else out = copies[i];
    std::erase_if(out, [&](Vertex v) { return sm.is_isolated(v); });
    return out;
  };
  for (std::size_t s : sources)
    if (copies_of(s).empty())
      throw InvalidInput("parameter 'sources': vertex " + std::to_string(s) + " is used by no face");
  auto dist = sm.add_property_map<Vertex, double>("v:geodesic_distance", 0.0).first;
  ctx.progress(0.1, "factoring");
  CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh, CGAL::Heat_method_3::Intrinsic_Delaunay> hm(sm);
  ctx.check_cancelled();
  for (std::size_t s : sources)
    for (Vertex v : copies_of(s)) hm.add_source(v);
  ctx.progress(0.6, "solving");
  hm.estimate_geodesic_distances(dist);
  result.distance = ScalarField{"distance", Location::vertex, ColorHint::magnitude, {}};
  result.distance.values.resize(mesh.num_vertices(), 0.0f);
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (!repaired) {
      const Vertex v{SurfaceMesh::size_type(i)};
      if (!sm.is_isolated(v)) result.distance.values[i] = float(dist[v]);
      continue;
    }
    const std::vector<Vertex> at = copies_of(i);
    double d = HUGE_VAL;
    for (Vertex v : at) d = std::min(d, dist[v]);
    if (!at.empty()) result.distance.values[i] = float(d);
  }
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(geodesic_distance, geodesic_distance,
                         {.title = "Geodesic distance (heat method)",
                          .description = "Approximate geodesic distance on a triangle mesh (a repaired copy "
                                         "when it is not manifold) from one or more source vertices, by the "
                                         "heat method on an intrinsic Delaunay triangulation.",
                          .area = "filters"})

}  // namespace cgview
