#include "filters_direct.h"

// The kernel first (filters_direct.h): distance.h calls CGAL::midpoint without including it.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Polygon_mesh_processing/distance.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#pragma GCC diagnostic pop

#include <algorithm>

namespace cgview::bench {

namespace PMP = CGAL::Polygon_mesh_processing;

double direct_hausdorff(const SurfaceMesh& a, const SurfaceMesh& b, double bound) {
  return std::max(PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(a, b, bound),
                  PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(b, a, bound));
}

void direct_repair(std::vector<Point3>& points, std::vector<std::vector<std::size_t>>& polygons, SurfaceMesh& sm) {
  PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  std::erase_if(polygons, [&](const std::vector<std::size_t>& f) {
    return CGAL::collinear(points[f[0]], points[f[1]], points[f[2]]);
  });
  PMP::repair_polygon_soup(points, polygons);
  PMP::orient_polygon_soup(points, polygons);
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  PMP::stitch_borders(sm);
  sm.collect_garbage();
}

}  // namespace cgview::bench
