// skeleton_distance: the symmetric Hausdorff and mean distance between two
// skeletons, sampled along their edges (measure_distance,
// skeleton/skeleton_measures.h): how far one skeleton of a mesh is from
// another (the paper's Figure 5).
//
//   SkeletonDistanceResult r = skeleton_distance(ours, mcf, {.spacing = 0.01});
//   std::printf("Hausdorff %g, mean %g\n", r.metrics.at("hausdorff"), r.metrics.at("mean"));
#pragma once

#include <string>
#include <vector>

#include "core/skeleton.h"
#include "registry/registry.h"

namespace cgview {

struct SkeletonDistanceParams {
  double spacing = 0;
  template <class V>
  void describe(V& v) {
    v.number("spacing", spacing,
             {.label = "Sample spacing",
              .min = 0,
              .help = "distance between samples along the edges (0: 1/500 of the bounding box's diagonal)"});
  }
};

struct SkeletonDistanceResult {
  Metrics metrics;  // hausdorff, mean
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("metrics", metrics);
  }
};

SkeletonDistanceResult skeleton_distance(const Skeleton& skeleton, const Skeleton& reference,
                                         const SkeletonDistanceParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
