// skeleton_projection: the paper's curve skeleton from projections
// (skeleton/skeleton_projection.h) as a registered algorithm.  Works on any
// triangle soup (silhouettes need no manifold); open meshes give votes
// only where both depth buffers see the inside.
#include "registry/registry.h"
#include "render/renderer_pool.h"
#include "skeleton/skeleton_metrics.h"
#include "skeleton/skeleton_projection.h"

namespace cgview::skeleton {
namespace {

struct Params : ProjectionParams {
  bool intermediate = false;
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
    v.integer(
        "contexts", contexts,
        {.label = "Render contexts", .min = 1, .max = 64, .help = "EGL contexts drawing at once", .advanced = true});
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

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  p.check();
  // The first context from the process's pool too (the others are, in
  // capture_cameras): a process that runs several jobs starts it once.
  render::RendererPool& pool = render::shared_pool(render::GlPlatform::automatic);
  std::unique_ptr<render::Renderer> renderer = pool.take();
  ProjectionResult r;
  try {
    r = skeleton_from_projections(*renderer, mesh, p, &ctx);
  } catch (...) {
    pool.give_back(nullptr);  // given up with its context, as capture_cameras does
    throw;
  }
  pool.give_back(std::move(renderer));
  Metrics m = metrics_table(skeleton_metrics(r.skeleton, mesh));
  m["faces_drawn"] = double(r.faces_drawn);
  m["render_seconds"] = r.render_seconds;
  m["vote_seconds"] = r.vote_seconds;
  m["thin_seconds"] = r.thin_seconds;
  m["render_cpu_seconds"] = r.render_cpu_seconds;
  m["vote_cpu_seconds"] = r.vote_cpu_seconds;
  m["thin_cpu_seconds"] = r.thin_cpu_seconds;
  AlgorithmResult out;
  out.artifacts.push_back({"skeleton", std::move(r.skeleton)});
  out.artifacts.push_back({"metrics", std::move(m)});
  if (p.intermediate) {
    out.artifacts.push_back({"votes", std::move(r.votes)});
    VoxelGrid view({p.image, p.image, 1}, Vec3{}, 1.0, VoxelType::uint8);
    for (int y = 0; y < p.image; ++y)  // rows from the bottom, as the grid's j
      for (int x = 0; x < p.image; ++x)
        view.set({x, p.image - 1 - y, 0}, float(r.first_view[std::size_t(y) * p.image + x]));
    out.artifacts.push_back({"first_view", std::move(view)});
  }
  ctx.progress(1.0, "done");
  return out;
}

}  // namespace
}  // namespace cgview::skeleton

CGVIEW_REGISTER_ALGORITHM(
    skeleton_projection, cgview::skeleton::Params, cgview::skeleton::run,
    {.title = "Skeleton from projections",
     .description = "The paper's curve skeleton: medial axes of silhouettes rendered from many views "
                    "vote in a voxel grid, thinned along the ridge of votes, merged and smoothed.",
     .area = "skeleton",
     .outputs = {{"skeleton", cgview::OutputKind::skeleton},
                 {"metrics", cgview::OutputKind::metrics},
                 {"votes", cgview::OutputKind::voxel_grid},
                 {"first_view", cgview::OutputKind::voxel_grid}}});
