// A curve skeleton from the 2D medial axes of a shape's projections (the
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
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "core/mesh.h"
#include "core/skeleton.h"
#include "core/voxel_grid.h"

namespace cgview {

class Context;

namespace render {
class Renderer;
struct ViewCapture;
}  // namespace render

namespace skeleton {

struct ProjectionParams {
  int views = 48;                // an even number in [2, 1000]: views / 2 antipodal pairs, one drawing each
  int image = 256;               // pixels on a side, [32, 2048]
  int grid = 128;                // voxels along the bounding box's longest side, [16, 512]
  int min_radius = 2;            // medial pixels nearer the border are dropped
  double threshold = 0.25;       // voxels with fewer votes than this x the most are out
  double min_branch = 0.05;      // shortest branch kept, x the bounding box's diagonal
  double branch_votes = 0.2;     // branches whose mean votes are below this x the main path's are pruned
  double merge_distance = 0.03;  // internal arcs shorter than this x the diagonal are collapsed
  int smoothing = 20;            // Laplacian iterations (lambda 0.5)
  int contexts = 2;              // rendering contexts at once (render/views.h)
  int render_faces =
      200000;  // a mesh with more faces is drawn decimated to at most these (vertex clustering); 0: never
  // Throws InvalidInput naming the parameter out of range.
  void check() const;
};

// (b) The (3,4) chamfer distance of each inside pixel to the outside (3 per
// pixel step, 4 per diagonal step; 0 outside; the image border is outside).
std::vector<std::uint16_t> chamfer_34(const std::vector<std::uint8_t>& mask, int width, int height);
// The centres of maximal discs with dt >= 3 * min_radius: 1 on the axis.
std::vector<std::uint8_t> medial_axis(const std::vector<std::uint16_t>& dt, int width, int height, int min_radius);

// (c) Votes (a float grid over the mesh's bounding box, `grid` voxels along
// its longest side, one voxel of margin) from views captured with their back
// depth (render::CaptureOptions; InvalidInput without), and for each voxel
// the mean radius (world units) of the medial discs that voted for it.
struct Votes {
  VoxelGrid grid;
  std::vector<float> radius;
};
Votes vote(const std::vector<render::ViewCapture>& views, const BBox& box, const ProjectionParams& p,
           const Context* ctx = nullptr);

// (d) The skeleton of the vote grid, nodes at voxel centres; `radius` (from
// vote) sets how far a branch covers the voxels around it (1.5 x the radius
// + 2 voxels, as TEASAR), how far apart along the skeleton the nodes where
// two meeting paths join must be (tunnels), and how far an end looks to
// close a loop (other meshes).
// With `inside` (the solid) and `max_loops` >= 0 (its genus), loops are
// tunnels: where the shortest-path trees meet themselves (neighbouring
// voxels whose paths join the skeleton further apart along it than their
// covering radii), the meetings that touch one another form a cut through
// a tunnel; each cut closes one loop, through its best voted meeting whose
// loop goes around a hole (the triangles from its centre to its edges cross
// the outside; a cut whose 8 best voted meetings go around none closes
// none), the best voted cuts first, at most max_loops.  Otherwise an
// end next to a far part of the skeleton through voted voxels closes one.
Skeleton thin(const VoxelGrid& votes, const std::vector<float>& radius, const ProjectionParams& p, int max_loops = -1,
              const std::function<bool(const Vec3&)>& inside = {});

// (e) Collapses internal arcs shorter than `merge_length` and smooths; a
// smoothing step that would take a node where `allowed` says no (outside the
// mesh) leaves it where it was.
void simplify(Skeleton& s, double merge_length, int smoothing_iterations,
              const std::function<bool(const Vec3&)>& allowed = {});

// All stages.  `votes`, when not null, receives the vote grid; `axis`, when
// not null, the first view's silhouette (1) with its medial axis (2).
struct ProjectionResult {
  Skeleton skeleton;
  VoxelGrid votes;
  std::vector<std::uint8_t> first_view;  // 0 outside, 1 inside, 2 medial axis; image x image, rows from the top
  double render_seconds = 0, vote_seconds = 0, thin_seconds = 0;              // vote: medial axes and votes
  double render_cpu_seconds = 0, vote_cpu_seconds = 0, thin_cpu_seconds = 0;  // the process's CPU time (all threads)
  int genus = -1;               // the mesh's, which bounds the loops; -1: not a closed, oriented mesh
  std::size_t faces_drawn = 0;  // the mesh's, or its decimated copy's (render_faces)
};
ProjectionResult skeleton_from_projections(render::Renderer& renderer, const Mesh& mesh, const ProjectionParams& p,
                                           const Context* ctx = nullptr);

}  // namespace skeleton
}  // namespace cgview
