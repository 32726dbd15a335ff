#include "filters_direct.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_ratio_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#pragma GCC diagnostic pop
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/smooth_shape.h>
#include <CGAL/subdivision_method_3.h>

#include <cmath>

namespace cgview::bench {

namespace PMP = CGAL::Polygon_mesh_processing;
namespace SMS = CGAL::Surface_mesh_simplification;

double mean_edge_length(const SurfaceMesh& sm) {
  double sum = 0;
  for (auto e : sm.edges())
    sum += std::sqrt(CGAL::squared_distance(sm.point(sm.source(sm.halfedge(e))), sm.point(sm.target(sm.halfedge(e)))));
  return sum / double(sm.number_of_edges());
}

void direct_simplify(SurfaceMesh& sm) {
  // On a closed triangle mesh an edge ratio of 0.25 is a face ratio of 0.25.
  SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> gh(sm);
  SMS::edge_collapse(sm, SMS::Count_ratio_stop_predicate<SurfaceMesh>(0.25),
                     CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()));
  sm.collect_garbage();
}

void direct_remesh(SurfaceMesh& sm) {
  PMP::isotropic_remeshing(faces(sm), mean_edge_length(sm), sm, CGAL::parameters::number_of_iterations(1));
  sm.collect_garbage();
}

void direct_smooth(SurfaceMesh& sm) {
  PMP::smooth_shape(sm, 1e-4, CGAL::parameters::number_of_iterations(1));
  sm.collect_garbage();
}

void direct_subdivide(SurfaceMesh& sm) {
  CGAL::Subdivision_method_3::Loop_subdivision(sm, CGAL::parameters::number_of_iterations(1));
}

}  // namespace cgview::bench
