// skeleton_segmentation (the paper's octopus figure): each face takes the
// branch of the skeleton nearest to its centroid among those it can see, the
// segment from the centroid to the branch's nearest point crossing no other
// face (so that a finger lying against a palm keeps its own branch). Where
// no branch is visible, the nearest one.  A categorical per-face field.
//
//   Mesh m = read_mesh("elephant.off");
//   SkeletonSegmentationResult r = skeleton_segmentation(m, skeleton_mcf(m).skeleton);
//   // r.branch.values[f]: face f's branch, an index of skeleton_branches(skeleton)
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "registry/registry.h"

namespace cgview {

struct SkeletonSegmentationParams {
  template <class V>
  void describe(V&) {}
};

struct SkeletonSegmentationResult {
  ScalarField branch;  // per face
  Metrics metrics;     // branches
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("branch", branch);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for an invalid skeleton, one without edges, or a mesh
// without faces.
SkeletonSegmentationResult skeleton_segmentation(const Mesh& mesh, const Skeleton& skeleton,
                                                 const SkeletonSegmentationParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
