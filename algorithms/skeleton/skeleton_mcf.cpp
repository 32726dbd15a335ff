// skeleton_mcf: CGAL's mean curvature flow skeletonization (Tagliasacchi,
// Alhashim, Olson and Zhang 2012, "Mean Curvature Skeletons"), the
// mesh-contraction family's reference, as a registered algorithm.  The
// contraction loop is CGAL's contract_until_convergence(), written out so
// that each iteration reports progress and can be cancelled.
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/boost/graph/helpers.h>

#include <cmath>
#include <numbers>

#include "core/surface_mesh.h"
#include "registry/registry.h"
#include "skeleton/skeleton_metrics.h"

namespace cgview {
namespace {

using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<SurfaceMesh>;

struct Params {
  double max_triangle_angle = 110;
  double min_edge_length = 0.002;
  double quality_speed_tradeoff = 0.1;
  bool medially_centered = true;
  double medially_centered_speed_tradeoff = 0.2;
  double area_variation_factor = 0.0001;
  int max_iterations = 500;
  template <class V>
  void describe(V& v) {
    v.number("max_triangle_angle", max_triangle_angle,
             {.label = "Max triangle angle (degrees)",
              .min = 90,
              .max = 179,
              .help = "edges opposite larger angles are split while contracting",
              .advanced = true});
    v.number("min_edge_length", min_edge_length,
             {.label = "Min edge length",
              .min = 1e-6,
              .max = 0.5,
              .help = "shorter edges collapse; a fraction of the bounding box's diagonal (CGAL: 0.002)",
              .advanced = true});
    v.number("quality_speed_tradeoff", quality_speed_tradeoff,
             {.label = "Quality/speed",
              .min = 1e-4,
              .max = 100,
              .help = "larger: faster contraction, a less smooth skeleton (w_H)",
              .advanced = true});
    v.boolean("medially_centered", medially_centered,
              {.label = "Medially centred", .help = "pull towards the medial axis (Voronoi poles)"});
    v.number("medially_centered_speed_tradeoff", medially_centered_speed_tradeoff,
             {.label = "Centring/speed",
              .min = 1e-4,
              .max = 100,
              .help = "weight of the medial pull (w_M)",
              .when = {"medially_centered", {"true"}}});
    v.number("area_variation_factor", area_variation_factor,
             {.label = "Convergence",
              .min = 1e-8,
              .max = 0.1,
              .help = "stop when the area changes by less than this fraction of the original in one iteration",
              .advanced = true});
    v.integer("max_iterations", max_iterations,
              {.label = "Max iterations", .min = 1, .max = 10000, .help = "contraction iterations at most"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  const char* remedy = "run repair and fill_holes on it first";
  SurfaceMesh sm = manifold_surface_mesh(mesh, "skeleton_mcf", remedy);
  if (!CGAL::is_closed(sm))
    throw InvalidInput(std::string("skeleton_mcf needs a closed mesh: this one has borders (") + remedy + ")");
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

  Skeleton s;
  s.vertex_to_node.assign(mesh.positions.size(), 0);
  for (auto v : CGAL::make_range(vertices(graph))) {
    const auto& pt = graph[v].point;
    s.nodes.push_back({pt.x(), pt.y(), pt.z()});
    for (auto mv : graph[v].vertices) s.vertex_to_node[std::size_t(mv)] = Index(v);
  }
  for (auto e : CGAL::make_range(edges(graph))) s.edges.push_back({Index(source(e, graph)), Index(target(e, graph))});
  Metrics m = metrics_table(skeleton_metrics(s, mesh));
  m["iterations"] = iterations;
  ctx.progress(1.0, "done");
  return {{{"skeleton", std::move(s)}, {"metrics", std::move(m)}}, {}};
}

}  // namespace
}  // namespace cgview

CGVIEW_REGISTER_ALGORITHM(
    skeleton_mcf, cgview::Params, cgview::run,
    {.title = "Skeleton by mean curvature flow (CGAL)",
     .description = "CGAL's Mean_curvature_flow_skeletonization: the surface contracted by mean "
                    "curvature flow to a curve, pulled towards the medial axis. Needs a closed manifold mesh.",
     .area = "skeleton",
     .outputs = {{"skeleton", cgview::OutputKind::skeleton}, {"metrics", cgview::OutputKind::metrics}}});
