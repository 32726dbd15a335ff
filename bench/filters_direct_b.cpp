#include "filters_direct.h"

#include <CGAL/Heat_method_3/Surface_mesh_geodesic_distances_3.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/compute_normal.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include <iterator>

namespace cgview::bench {

namespace PMP = CGAL::Polygon_mesh_processing;

void direct_normals(SurfaceMesh& sm) {
  auto n = sm.add_property_map<SurfaceMesh::Vertex_index, Kernel::Vector_3>("v:bench_normal").first;
  PMP::compute_vertex_normals(sm, n);
}

void direct_geodesic_distance(SurfaceMesh& sm) {
  auto d = sm.add_property_map<SurfaceMesh::Vertex_index, double>("v:bench_distance", 0.0).first;
  CGAL::Heat_method_3::Surface_mesh_geodesic_distances_3<SurfaceMesh, CGAL::Heat_method_3::Intrinsic_Delaunay> hm(sm);
  hm.add_source(SurfaceMesh::Vertex_index(0));
  hm.estimate_geodesic_distances(d);
}

void direct_components(SurfaceMesh& sm) {
  auto c = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:bench_component").first;
  PMP::connected_components(sm, c);
  PMP::keep_largest_connected_components(sm, 1);
  sm.collect_garbage();
}

void direct_fill_holes(SurfaceMesh& sm) {
  using Halfedge = SurfaceMesh::Halfedge_index;
  std::vector<Halfedge> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  for (Halfedge h : cycles) {
    if (CGAL::halfedges_around_face(h, sm).size() > 1000) continue;
    std::vector<SurfaceMesh::Face_index> new_faces;
    std::vector<SurfaceMesh::Vertex_index> new_vertices;
    PMP::triangulate_refine_and_fair_hole(sm, h, std::back_inserter(new_faces), std::back_inserter(new_vertices));
  }
  sm.collect_garbage();
}

}  // namespace cgview::bench
