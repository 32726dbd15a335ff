// skeleton_projection: a curve skeleton from the 2D medial axes of a shape's projections (the
// CGView paper, section 3.1), each stage a function of its own:
//
// (a) `views` orthographic directions in antipodal pairs (d and -d, d on a
//     Fibonacci sphere), silhouettes and depth from the EGL renderer
//     (render/views.h), one drawing per pair: its depth is where each
//     pixel's ray enters the shape (depth from d), its back depth where the
//     ray leaves it (the depth from -d), and -d's silhouette is d's
//     mirrored, so its medial axis casts the same rays.  A
//     mesh of more than `render_faces` faces is drawn decimated by vertex
//     clustering (core/cluster_decimate.h): its cells are far below a pixel,
//     and the drawing costs by the triangle;
// (b) medial_axis: the (3,4) chamfer distance transform of each silhouette
//     (Borgefors 1986; Sanniti di Baja 1994's skeletons), whose centres of
//     maximal discs are the medial axis: a pixel p such that no neighbour q
//     has dt(q) >= dt(p) + w(p, q) (w = 3 edge-, 4 corner-wise); pixels
//     closer than `min_radius` pixels to the border are dropped (the
//     spurious branches of a noisy outline);
// (c) vote: each medial pixel of radius w casts its ray; the voxels from
//     where it enters the shape to min(where it leaves, entry + 2 w) get a
//     vote, and as the antipode's ray those from where it leaves back to
//     max(entry, exit - 2 w) (inside the shape by the depth buffers, and no
//     deeper than the disc the pixel is the centre of); a ray knows only
//     its first and last surfaces, so for a closed mesh the votes are then
//     kept to its solid (voxelize, at the votes' voxel size: the hollow of
//     a pipe seen from the side is voted across otherwise);
// (d) thin: the voxels with at least `threshold` x the most votes, reached
//     through those with a fifth of that (every voted voxel where that would
//     part them); an intensity-driven shortest-path tree from the most voted voxel (a step
//     costs its length over the voxel's normalized votes squared, so paths
//     run along the ridge of votes, cf. Yim et al. 2000); branches taken as
//     in TEASAR (Sato et al. 2000): the farthest voxel not yet covered gives a
//     path back to the tree, kept if long enough and voted enough (low-valued
//     branches pruned), and the voxels within 1.5 x the local radius (the
//     medial discs' that voted) around it are covered; then loops: for a
//     closed mesh, its tunnels (at most its genus): the shortest-path
//     trees meet themselves around a tunnel, two neighbouring voxels whose
//     paths join the skeleton far apart along it; one loop for each cut of
//     such meetings, through the best voted meeting whose loop goes around
//     a hole; for other meshes, an end near (through voted voxels) a part
//     of the skeleton far along it (see thin);
// (e) simplify: internal arcs shorter than `merge_distance` collapsed (branch
//     nodes that are too close merged), then endpoint-preserving Laplacian
//     smoothing of the nodes inside branches, which frees them from voxel
//     centres.
//
// Each stage has a header of its own under skeleton/projection/:
// medial_axis.h (b), vote.h (c), thin.h (d), simplify_skeleton.h (e).
// Works on any triangle soup (silhouettes need no manifold); open meshes
// give votes only where both depth buffers see the inside.
//
//   SkeletonProjectionResult r = skeleton_projection(mesh, {.views = 96, .grid = 192});
//   write_skeleton(r.skeleton, "skeleton.cg");
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "core/voxel_grid.h"
#include "registry/registry.h"

namespace cgview {

struct SkeletonProjectionParams {
  int views = 48;                // an even number: views / 2 antipodal pairs, one drawing each
  int image = 256;               // pixels on a side
  int grid = 128;                // voxels along the bounding box's longest side
  int min_radius = 2;            // medial pixels nearer the border are dropped
  double threshold = 0.25;       // voxels with fewer votes than this x the most are out
  double min_branch = 0.05;      // shortest branch kept, x the bounding box's diagonal
  double branch_votes = 0.2;     // branches whose mean votes are below this x the main path's are pruned
  double merge_distance = 0.03;  // internal arcs shorter than this x the diagonal are collapsed
  int smoothing = 20;            // Laplacian iterations (lambda 0.5)
  int contexts = 0;              // rendering contexts at once; 0: render::automatic_contexts
  int render_faces = 200000;     // a mesh with more faces is drawn decimated to at most these; 0: never
  bool intermediate = false;     // also the vote grid and the first view
  template <class V>
  void describe(V& v) {
    v.integer("views", views,
              {.label = "Views", .min = 2, .max = 1000, .help = "silhouettes, in antipodal pairs (even)"});
    v.integer("image", image,
              {.label = "Image size", .min = 32, .max = 2048, .help = "pixels on a side of each silhouette"});
    v.integer(
        "grid", grid,
        {.label = "Vote grid", .min = 16, .max = 512, .help = "voxels along the longest side of the bounding box"});
    v.integer("min_radius", min_radius,
              {.label = "Medial axis: min radius",
               .min = 0,
               .max = 100,
               .help = "medial pixels nearer the outline (pixels) are dropped",
               .advanced = true});
    v.number("threshold", threshold,
             {.label = "Vote threshold",
              .min = 0.001,
              .max = 0.999,
              .help = "voxels with fewer votes than this x the most are out"});
    v.number("min_branch", min_branch,
             {.label = "Shortest branch", .min = 0, .max = 0.99, .help = "x the bounding box's diagonal"});
    v.number("branch_votes", branch_votes,
             {.label = "Branch votes",
              .min = 0,
              .max = 1,
              .help = "branches whose mean votes are below this x the main path's are pruned",
              .advanced = true});
    v.number("merge_distance", merge_distance,
             {.label = "Merge distance",
              .min = 0,
              .max = 0.99,
              .help = "internal arcs shorter than this x the diagonal are collapsed",
              .advanced = true});
    v.integer("smoothing", smoothing,
              {.label = "Smoothing", .min = 0, .max = 1000, .help = "Laplacian iterations; ends and junctions stay"});
    v.integer("contexts", contexts,
              {.label = "Render contexts",
               .min = 0,
               .max = 64,
               .help = "EGL contexts drawing at once; 0: 1 on a GPU, 2 on a software renderer",
               .advanced = true});
    v.integer("render_faces", render_faces,
              {.label = "Faces drawn",
               .min = 0,
               .max = 1 << 30,
               .help = "bigger meshes are drawn decimated (vertex clustering); 0: never",
               .advanced = true});
    v.boolean("intermediate", intermediate,
              {.label = "Keep intermediate results",
               .help = "also the vote grid and the first view's silhouette with its medial axis",
               .advanced = true});
  }
};

struct SkeletonProjectionResult {
  Skeleton skeleton;
  // skeleton_metrics' measures, the faces drawn, and each stage's wall and
  // process CPU seconds (render, vote: medial axes and votes, thin).
  Metrics metrics;
  std::optional<VoxelGrid> votes;       // with `intermediate`
  std::optional<VoxelGrid> first_view;  // with `intermediate`: 0 outside, 1 inside, 2 medial axis
  int genus = -1;                       // the mesh's, which bounds the loops; -1: not a closed, oriented mesh
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("skeleton", skeleton);
    v("metrics", metrics);
    v("votes", votes);
    v("first_view", first_view);
  }
};

// Draws with a context of the process's EGL pool (Mesa's llvmpipe without a
// GPU).  Throws InvalidInput for a mesh without faces or an odd `views`.
SkeletonProjectionResult skeleton_projection(const Mesh& mesh, const SkeletonProjectionParams& p = {},
                                             Context* ctx = nullptr);

}  // namespace cgview
