#include "skeleton/skeleton_mcf.h"

#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <numbers>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "skeleton/skeleton_measures.h"

namespace cgview {

namespace {
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<SurfaceMesh>;
}  // namespace

SkeletonMcfResult skeleton_mcf(const Mesh& mesh, const SkeletonMcfParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  std::vector<std::string> warnings;
  bool repaired = false;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "skeleton_mcf", p.repair, warnings, &repaired);
  if (!CGAL::is_closed(sm))
    throw InvalidInput(std::string("skeleton_mcf needs a closed mesh: this one has borders") +
                       (repaired ? " once repaired" : "") + " (run fill_holes on it first)");
  if (!CGAL::is_triangle_mesh(sm)) throw InvalidInput("skeleton_mcf needs a triangle mesh");
  const BBox box = bounding_box(mesh);
  Skeletonization mcs(sm);
  mcs.set_max_triangle_angle(p.max_triangle_angle * std::numbers::pi / 180.0);
  mcs.set_min_edge_length(p.min_edge_length * box.diagonal());
  mcs.set_quality_speed_tradeoff(p.quality_speed_tradeoff);
  mcs.set_is_medially_centered(p.medially_centered);
  mcs.set_medially_centered_speed_tradeoff(p.medially_centered_speed_tradeoff);
  mcs.set_area_variation_factor(p.area_variation_factor);
  mcs.set_max_iterations(std::size_t(p.max_iterations));

  const double original = CGAL::Polygon_mesh_processing::area(sm);
  double last = 0;
  int iterations = 0;
  for (; iterations < p.max_iterations;) {
    ctx.check_cancelled();
    mcs.contract_geometry();
    mcs.remesh();
    mcs.detect_degeneracies();
    ++iterations;
    const double area = CGAL::Polygon_mesh_processing::area(mcs.meso_skeleton());
    const double change = std::abs(last - area) / original;
    // Progress: the area shrinks towards zero, roughly geometrically.
    ctx.progress(std::min(0.95, 1.0 - area / original), "contracting");
    if (change < p.area_variation_factor) break;
    last = area;
  }
  ctx.progress(0.95, "converting to a skeleton");
  Skeletonization::Skeleton graph;
  mcs.convert_to_skeleton(graph);

  SkeletonMcfResult result;
  result.warnings = std::move(warnings);
  Skeleton& s = result.skeleton;
  // Each vertex of sm's node; vertex i of the mesh is vertex i of sm, unless
  // repaired: then the first of the copy's vertices at its position.
  std::vector<Index> node_of(sm.number_of_vertices() + sm.number_of_removed_vertices(), 0);
  for (auto v : CGAL::make_range(vertices(graph))) {
    const auto& pt = graph[v].point;
    s.nodes.push_back({pt.x(), pt.y(), pt.z()});
    for (auto mv : graph[v].vertices) node_of[std::size_t(mv)] = Index(v);
  }
  s.vertex_to_node.assign(mesh.positions.size(), 0);
  if (!repaired) {
    for (std::size_t i = 0; i < s.vertex_to_node.size() && i < node_of.size(); ++i) s.vertex_to_node[i] = node_of[i];
  } else {
    const std::vector<std::vector<SurfaceMesh::Vertex_index>> copies = vertices_after_repair(mesh, sm);
    for (std::size_t i = 0; i < s.vertex_to_node.size(); ++i)
      if (!copies[i].empty()) s.vertex_to_node[i] = node_of[std::size_t(copies[i][0])];
  }
  for (auto e : CGAL::make_range(edges(graph))) s.edges.push_back({Index(source(e, graph)), Index(target(e, graph))});
  result.metrics = metrics_table(measure_skeleton(s, mesh));
  result.metrics["iterations"] = iterations;
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(skeleton_mcf, skeleton_mcf,
                         {.title = "Skeleton by mean curvature flow (CGAL)",
                          .description = "CGAL's Mean_curvature_flow_skeletonization: the surface contracted by mean "
                                         "curvature flow to a curve, pulled towards the medial axis. Needs a closed "
                                         "mesh (one that is not manifold is repaired first).",
                          .area = "skeleton"})

}  // namespace cgview
