// Measures of a curve skeleton, alone and against its mesh, and a distance
// between two skeletons: what the paper's Figure 5 compares, and what the
// skeleton_metrics and skeleton_distance algorithms report
// (skeleton/skeleton_metrics.h, skeleton/skeleton_distance.h).
//
// - nodes, edges, branches (skeleton_branches), endpoints (degree 1),
//   junctions (degree 3+), loops (the cycle rank E - V + C), length;
// - inside: the fraction of nodes inside the mesh (RayCaster::inside: needs a
//   closed, outward-oriented mesh);
// - centredness, per node of degree 2 (a node inside a branch): in the plane
//   through the node normal to the branch, 16 rays find the cross-section;
//   the midpoints of opposite chords are the projections of the section's
//   centre c onto lines through the node, so c = node + 2 mean(midpoint -
//   node) (exact for a circle), and the local radius r is the mean half
//   chord; centredness = |c - node| / r (0: centred; 1: on the surface).
//   Mean and maximum over the nodes measured.
// - distance(a, b): both skeletons sampled along their edges every
//   `spacing`; from each sample, the distance to the nearest point of the
//   other skeleton's edges; symmetric Hausdorff = the largest, mean = the
//   mean of the two directed means.
#pragma once

#include "core/mesh.h"
#include "core/skeleton.h"
#include "registry/registry.h"

namespace cgview {

struct SkeletonMetrics {
  std::size_t nodes = 0, edges = 0, branches = 0, endpoints = 0, junctions = 0, loops = 0, components = 0;
  double length = 0;
  double inside_fraction = 0;
  std::size_t centredness_nodes = 0;  // nodes where it could be measured
  double centredness_mean = 0, centredness_max = 0;
};

// Throws InvalidInput for an invalid skeleton or a mesh with no faces.
SkeletonMetrics measure_skeleton(const Skeleton& s, const Mesh& mesh);
// The same, without the measures that need a mesh.
SkeletonMetrics skeleton_shape_metrics(const Skeleton& s);
// As a metrics table (the names above).
Metrics metrics_table(const SkeletonMetrics& m);

// The endpoints once spurs are pruned: terminal branches (from an end to a
// branch node) shorter than `length` removed, again until none is left (a
// hand's fingers go, then the arm ends at the hand), so that skeletons with
// and without bumps compare by their limbs.
std::size_t endpoints_after_pruning(Skeleton s, double length);
// Where those ends are.
std::vector<Vec3> ends_after_pruning(Skeleton s, double length);
// How many ends of `a` pair with a different end of `b` no further than
// `near` (the closest pairs first): the limbs two skeletons share.
std::size_t matched_ends(const std::vector<Vec3>& a, const std::vector<Vec3>& b, double near);

struct SkeletonDistance {
  double hausdorff = 0, mean = 0;
};
// spacing <= 0: 1/500 of the diagonal of both skeletons' bounding box.
SkeletonDistance measure_distance(const Skeleton& a, const Skeleton& b, double spacing = 0);

}  // namespace cgview
