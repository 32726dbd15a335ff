// The `repair` parameter of the algorithms that need a manifold mesh
// (simplify, smooth, remesh, subdivide, fill_holes, components,
// geodesic_distance, hausdorff, sdf_segmentation, skeleton_mcf), described
// once: on by default, so that the scans students have (a non-manifold
// edge or vertex, a duplicate face) run on a repaired copy with a warning
// saying what the repair changed, instead of being refused.
//
//   struct SimplifyParams {
//     bool repair = true;
//     template <class V> void describe(V& v) { ...; describe_repair(v, repair); }
//   };
#pragma once

#include "registry/registry.h"

namespace cgview {

template <class V>
void describe_repair(V& v, bool& repair) {
  v.boolean("repair", repair,
            {.label = "Repair first",
             .help = "when the mesh is not manifold, run on a repaired copy (as the repair filter does: duplicate "
                     "points merged, degenerate and duplicate faces removed, non-manifold edges and vertices "
                     "split) and say what changed in a warning; off: refuse such a mesh. The stored mesh is "
                     "never changed"});
}

}  // namespace cgview
