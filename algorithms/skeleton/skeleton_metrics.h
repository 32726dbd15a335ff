// skeleton_metrics: the measures of skeleton/skeleton_measures.h as an
// algorithm, for the comparison table of several skeletons of one mesh (the
// paper's Figure 5): nodes, branches, endpoints, junctions, loops and length
// of a skeleton, the fraction of its nodes inside the mesh, and how centred
// it is in the mesh's cross-sections.
//
//   Skeleton s = read_skeleton("elephant.cg");
//   SkeletonMetricsResult r = skeleton_metrics(read_mesh("elephant.off"), s);
//   std::printf("%g loops\n", r.metrics.at("loops"));
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "registry/registry.h"
#include "skeleton/skeleton_measures.h"

namespace cgview {

struct SkeletonMetricsParams {
  template <class V>
  void describe(V&) {}
};

struct SkeletonMetricsResult {
  Metrics metrics;  // metrics_table's names
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("metrics", metrics);
  }
};

// Throws InvalidInput for an invalid skeleton or a mesh with no faces.
SkeletonMetricsResult skeleton_metrics(const Mesh& mesh, const Skeleton& skeleton, const SkeletonMetricsParams& p = {},
                                       Context* ctx = nullptr);

}  // namespace cgview
