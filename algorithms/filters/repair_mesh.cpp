#include "filters/repair_mesh.h"

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>

#include <algorithm>
#include <array>
#include <map>
#include <string>

#include "core/errors.h"

namespace cgview {

namespace PMP = CGAL::Polygon_mesh_processing;

SurfaceMesh repair_to_surface_mesh(const Mesh& mesh, bool stitch, RepairReport& report) {
  std::vector<Point3> points;
  points.reserve(mesh.num_vertices());
  for (const Vec3& v : mesh.positions) points.emplace_back(v.x, v.y, v.z);
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.num_faces());
  for (const Tri& f : mesh.faces) polygons.push_back({f[0], f[1], f[2]});
  report.vertices_before = points.size();
  report.faces_before = polygons.size();

  report.vertices_merged = PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  // repair_polygon_soup removes faces with fewer than three distinct points;
  // faces of zero area (three collinear points) go here, by an exact test.
  std::erase_if(polygons, [&](const std::vector<std::size_t>& f) {
    return CGAL::collinear(points[f[0]], points[f[1]], points[f[2]]);
  });
  const std::size_t points1 = points.size();
  PMP::repair_polygon_soup(points, polygons);
  report.isolated_vertices_removed = points1 - points.size();
  report.faces_removed = report.faces_before - polygons.size();
  if (polygons.empty()) throw InvalidInput("repair: every face is degenerate");

  const std::size_t points2 = points.size();
  PMP::orient_polygon_soup(points, polygons);
  report.vertices_duplicated = points.size() - points2;
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw InvalidInput("repair: the oriented soup is still not a polygon mesh");
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  if (stitch) {
    report.borders_stitched = PMP::stitch_borders(sm);
    sm.collect_garbage();
  }
  return sm;
}

namespace {

// "4 vertices duplicated to split non-manifold edges and vertices, 1
// degenerate or duplicate face removed": what the repair changed, the
// counts that are not zero.
std::string what_changed(const RepairReport& rep) {
  std::string out;
  auto add = [&](std::size_t n, const char* one, const char* many) {
    if (n == 0) return;
    if (!out.empty()) out += ", ";
    out += std::to_string(n) + " " + (n == 1 ? one : many);
  };
  add(rep.vertices_duplicated, "vertex duplicated to split non-manifold edges and vertices",
      "vertices duplicated to split non-manifold edges and vertices");
  add(rep.faces_removed, "degenerate or duplicate face removed", "degenerate or duplicate faces removed");
  add(rep.vertices_merged, "duplicate point merged", "duplicate points merged");
  add(rep.isolated_vertices_removed, "isolated vertex removed", "isolated vertices removed");
  add(rep.borders_stitched, "border stitched", "borders stitched");
  return out.empty() ? "faces reoriented consistently" : out;
}

using PositionKey = std::array<double, 3>;
PositionKey key_of(const Point3& p) { return {p.x(), p.y(), p.z()}; }
PositionKey key_of(const Vec3& p) { return {p.x, p.y, p.z}; }

}  // namespace

SurfaceMesh halfedge_mesh_for(const Mesh& mesh, const char* who, bool repair, std::vector<std::string>& warnings,
                              bool* repaired) {
  if (repaired) *repaired = false;
  if (!repair) return manifold_surface_mesh(mesh, who, "set 'repair' to repair it first, or run repair on it");
  SurfaceMeshResult r = to_surface_mesh(mesh);
  if (r.skipped_faces == 0) return std::move(r.mesh);
  RepairReport rep;
  SurfaceMesh sm = repair_to_surface_mesh(mesh, true, rep);
  warnings.push_back(std::string(who) + ": the mesh was not manifold (" + std::to_string(r.skipped_faces) +
                     (r.skipped_faces == 1 ? " face" : " faces") +
                     " did not fit a halfedge structure) and a copy was repaired first: " + what_changed(rep));
  if (repaired) *repaired = true;
  return sm;
}

std::vector<std::int64_t> faces_after_repair(const Mesh& mesh, const SurfaceMesh& repaired) {
  using Corners = std::array<PositionKey, 3>;
  auto sorted = [](Corners c) {
    std::sort(c.begin(), c.end());
    return c;
  };
  std::map<Corners, std::int64_t> face_at;
  for (SurfaceMesh::Face_index f : repaired.faces()) {
    Corners c{};
    int k = 0;
    for (SurfaceMesh::Vertex_index v : CGAL::vertices_around_face(repaired.halfedge(f), repaired))
      if (k < 3) c[std::size_t(k++)] = key_of(repaired.point(v));
    face_at.emplace(sorted(c), std::int64_t(f.idx()));
  }
  std::vector<std::int64_t> out(mesh.num_faces(), -1);
  for (std::size_t i = 0; i < mesh.num_faces(); ++i) {
    const Tri& t = mesh.faces[i];
    const auto it = face_at.find(
        sorted({key_of(mesh.positions[t[0]]), key_of(mesh.positions[t[1]]), key_of(mesh.positions[t[2]])}));
    if (it != face_at.end()) out[i] = it->second;
  }
  return out;
}

std::vector<std::vector<SurfaceMesh::Vertex_index>> vertices_after_repair(const Mesh& mesh,
                                                                          const SurfaceMesh& repaired) {
  std::map<PositionKey, std::vector<SurfaceMesh::Vertex_index>> at;
  for (SurfaceMesh::Vertex_index v : repaired.vertices()) at[key_of(repaired.point(v))].push_back(v);
  std::vector<std::vector<SurfaceMesh::Vertex_index>> out(mesh.num_vertices());
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i)
    if (const auto it = at.find(key_of(mesh.positions[i])); it != at.end()) out[i] = it->second;
  return out;
}

}  // namespace cgview
