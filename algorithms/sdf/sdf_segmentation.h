// sdf_segmentation: segment ids per face from our SDF values, by CGAL's
// segmentation_from_sdf_values (soft clustering of the log-normalized values
// by a Gaussian mixture, then a graph cut that prefers cuts along concave
// edges: Shapira et al. 2008, section 4).
//
//   Mesh m = read_mesh("elephant.off");
//   sdf::SdfSegmentationResult r = sdf::sdf_segmentation(m, {.clusters = 4});
//   std::printf("%g segments\n", r.metrics.at("segments"));
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {

struct SdfSegmentationParams {
  int clusters = 5;
  double smoothing_lambda = 0.26;
  bool cluster_ids = false;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  SdfParams sdf{};     // the SDF the segments are cut from
  template <class V>
  void describe(V& v) {
    v.integer("clusters", clusters,
              {.label = "Clusters",
               .min = 1,
               .max = 32,
               .help = "levels of the soft clustering of SDF values (CGAL's number_of_clusters)"});
    v.number("smoothing_lambda", smoothing_lambda,
             {.label = "Smoothing",
              .min = 0,
              .max = 1,
              .help = "weight of the surface's concave edges in the graph cut (0: none)"});
    v.boolean(
        "cluster_ids", cluster_ids,
        {.label = "Cluster ids", .help = "give each face its cluster (SDF level) instead of its connected segment"});
    describe_repair(v, repair);
    sdf.describe(v);
  }
};

struct SdfSegmentationResult {
  ScalarField segments;  // per face: its segment (or cluster) id, categorical
  Metrics metrics;       // segments, faces
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("segments", segments);
    v("metrics", metrics);
  }
};

// A mesh that is not manifold is cut on a repaired copy (`repair`, on by
// default: a warning says what changed); the segments are still one per
// face of `mesh`, a face the repair removed (degenerate) taking a
// neighbour's.  Throws InvalidInput for a mesh without faces, or one that
// is not manifold with `repair` off.
SdfSegmentationResult sdf_segmentation(const Mesh& mesh, const SdfSegmentationParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview::sdf
