// The direct side of filters_bench: each filter's CGAL calls, with the same
// settings as its file in algorithms/filters/, on a CGAL::Surface_mesh.  In
// three files (filters_direct_*.cpp) that build side by side: together, one
// of the heaviest units of the build.
#pragma once

#include <cstddef>
#include <vector>

#include "core/surface_mesh.h"

namespace cgview::bench {

double mean_edge_length(const SurfaceMesh& sm);

// filters_direct_a.cpp
void direct_simplify(SurfaceMesh& sm);   // Garland-Heckbert, a face ratio of 0.25
void direct_remesh(SurfaceMesh& sm);     // 1 iteration, the mean edge length
void direct_smooth(SurfaceMesh& sm);     // mean curvature flow, 1 iteration
void direct_subdivide(SurfaceMesh& sm);  // Loop, 1 iteration

// filters_direct_b.cpp
void direct_normals(SurfaceMesh& sm);
void direct_geodesic_distance(SurfaceMesh& sm);  // heat method, intrinsic Delaunay, from vertex 0
void direct_components(SurfaceMesh& sm);         // keep the largest
void direct_fill_holes(SurfaceMesh& sm);         // refine and fair, holes up to 1000 edges

// filters_direct_c.cpp
// Bounded-error Hausdorff distance both ways.
double direct_hausdorff(const SurfaceMesh& a, const SurfaceMesh& b, double bound);
// Soup repair, orientation and stitching, as algorithms/filters/repair.cpp.
void direct_repair(std::vector<Point3>& points, std::vector<std::vector<std::size_t>>& polygons, SurfaceMesh& sm);

}  // namespace cgview::bench
