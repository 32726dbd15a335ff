#include "filters/repair_mesh.h"

#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>

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

SurfaceMesh halfedge_mesh_for(const Mesh& mesh, const char* who, bool repair, std::vector<std::string>& warnings) {
  if (!repair) return manifold_surface_mesh(mesh, who, "set 'repair' to repair it first, or run repair on it");
  SurfaceMeshResult r = to_surface_mesh(mesh);
  if (r.skipped_faces == 0) return std::move(r.mesh);
  RepairReport rep;
  SurfaceMesh sm = repair_to_surface_mesh(mesh, true, rep);
  warnings.push_back(
      std::string(who) + ": the mesh was not manifold (" + std::to_string(r.skipped_faces) +
      " faces did not fit a halfedge structure) and was repaired first: " + std::to_string(rep.faces_removed) +
      " faces removed, " + std::to_string(rep.vertices_merged) + " vertices merged, " +
      std::to_string(rep.vertices_duplicated) + " duplicated to split non-manifold edges and vertices, " +
      std::to_string(rep.borders_stitched) + " borders stitched");
  return sm;
}

}  // namespace cgview
