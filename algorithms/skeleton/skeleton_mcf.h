// skeleton_mcf: CGAL's mean curvature flow skeletonization (Tagliasacchi,
// Alhashim, Olson and Zhang 2012, "Mean Curvature Skeletons"), the
// mesh-contraction family's reference.  The contraction loop is CGAL's
// contract_until_convergence(), written out so that each iteration reports
// progress and can be cancelled.
//
//   Mesh m = read_mesh("elephant.off");
//   SkeletonMcfResult r = skeleton_mcf(m, {.max_iterations = 100});
//   std::printf("%zu nodes, %g loops\n", r.skeleton.nodes.size(), r.metrics.at("loops"));
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct SkeletonMcfParams {
  double max_triangle_angle = 110;
  double min_edge_length = 0.002;
  double quality_speed_tradeoff = 0.1;
  bool medially_centered = true;
  double medially_centered_speed_tradeoff = 0.2;
  double area_variation_factor = 0.0001;
  int max_iterations = 500;
  bool repair = true;  // describe_repair (filters/repair_param.h)
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
    describe_repair(v, repair);
  }
};

struct SkeletonMcfResult {
  Skeleton skeleton;  // with vertex_to_node: each mesh vertex's node
  Metrics metrics;    // metrics_table's names (skeleton/skeleton_measures.h), and iterations
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("skeleton", skeleton);
    v("metrics", metrics);
  }
};

// A mesh that is not manifold is contracted as a repaired copy (`repair`,
// on by default: a warning says what changed; vertex_to_node stays one
// node per vertex of `mesh`).  Throws InvalidInput for a mesh that is not
// closed (after the repair), or not manifold with `repair` off.
SkeletonMcfResult skeleton_mcf(const Mesh& mesh, const SkeletonMcfParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
