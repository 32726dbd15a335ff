#include "skeleton/skeleton_projection.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <ctime>
#include <future>
#include <memory>
#include <optional>
#include <thread>

#include "core/cluster_decimate.h"
#include "core/mesh_report.h"
#include "rays/ray_caster.h"
#include "render/renderer.h"
#include "render/renderer_pool.h"
#include "render/views.h"
#include "skeleton/projection/medial_axis.h"
#include "skeleton/projection/simplify_skeleton.h"
#include "skeleton/projection/thin.h"
#include "skeleton/projection/vote.h"
#include "skeleton/skeleton_measures.h"
#include "voxel/voxelize.h"

namespace cgview {

namespace skeleton {
namespace {

// A stage's wall and process CPU seconds (all threads: the views and the
// votes use several).
struct Stopwatch {
  std::chrono::steady_clock::time_point wall = std::chrono::steady_clock::now();
  std::clock_t cpu = std::clock();
  // The time since the start (or the last stop), and starts again.
  void stop(double& wall_seconds, double& cpu_seconds) {
    const auto w = std::chrono::steady_clock::now();
    const std::clock_t c = std::clock();
    wall_seconds = std::chrono::duration<double>(w - wall).count();
    cpu_seconds = double(c - cpu) / CLOCKS_PER_SEC;
    wall = w;
    cpu = c;
  }
};

// What the stages give, before it becomes the result's artifacts.
struct Pipeline {
  Skeleton skeleton;
  VoxelGrid votes;
  std::vector<std::uint8_t> first_view;  // 0 outside, 1 inside, 2 medial axis; image x image, rows from the top
  double render_seconds = 0, vote_seconds = 0, thin_seconds = 0;              // vote: medial axes and votes
  double render_cpu_seconds = 0, vote_cpu_seconds = 0, thin_cpu_seconds = 0;  // the process's CPU time (all threads)
  int genus = -1;
  std::size_t faces_drawn = 0;  // the mesh's, or its decimated copy's (render_faces)
  int contexts = 1;             // render contexts the views were drawn with (the parameter, or automatic)
};

// All stages, (a) to (e).
Pipeline run_stages(render::Renderer& renderer, const Mesh& mesh, const SkeletonProjectionParams& p,
                    const Context* ctx) {
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: it has no silhouette");
  const BBox box = bounding_box(mesh);
  Pipeline out;
  Stopwatch watch;
  if (ctx) ctx->progress(0.0, "rendering silhouettes");
  // One drawing per antipodal pair: an orthographic view's back depth is its
  // antipode's depth, and its silhouette the antipode's mirrored.
  std::vector<render::CameraMatrices> cameras;
  for (const Vec3& d : render::sphere_directions(p.views / 2))
    cameras.push_back(render::orthographic_view(d, box, p.image, p.image));
  // The silhouettes of a big mesh from a decimated copy (the bounding box,
  // the cameras and the inside tests stay the full mesh's).
  Mesh decimated;
  if (p.render_faces > 0 && mesh.faces.size() > std::size_t(p.render_faces))
    decimated = cluster_decimate(mesh, {std::size_t(p.render_faces)}).mesh;
  const Mesh& drawn = decimated.faces.empty() ? mesh : decimated;
  out.faces_drawn = drawn.faces.size();
  // What needs the mesh alone, on a thread of its own while the views are
  // drawn: its report (whether it is closed, its genus), its ray caster (the
  // inside tests) and, for a closed mesh, its solid at the votes' voxel size
  // (the drawn copy: the surface's voxels and those it encloses).
  struct Solid {
    MeshReport report;
    std::unique_ptr<RayCaster> caster;
    std::optional<VoxelGrid> grid;
  };
  // Its context passes cancellation on, not progress: the job's progress
  // is this thread's (voxelize would report its own fractions as the
  // whole run's, and a job's progress function need not be thread-safe).
  Context solid_ctx(nullptr, [ctx] { return ctx && ctx->cancelled(); });
  std::future<Solid> solid_future = std::async(std::launch::async, [&] {
    Solid solid{mesh_report(mesh), std::make_unique<RayCaster>(mesh), std::nullopt};
    if (solid.report.closed) {
      VoxelizeParams vp;
      vp.voxel_size = vote_voxel_size(box, p.grid);
      vp.box = box;  // the votes' grid, voxel for voxel (a decimated copy's own box is smaller)
      vp.threads = 1;
      solid.grid = voxelize(drawn, vp, &solid_ctx).grid;
    }
    return solid;
  });
  out.contexts = p.contexts > 0 ? p.contexts : render::automatic_contexts(renderer);
  // Each view drawn counts, on whichever context's thread drew it, and is a
  // point at which a cancelled job stops; the progress is told from this
  // thread alone (the other contexts draw at its pace), over [0, 0.4],
  // about 50 times in all.
  std::atomic<std::size_t> drawn_views{0};
  const std::thread::id job_thread = std::this_thread::get_id();
  const std::size_t every = std::max<std::size_t>(1, cameras.size() / 50);
  std::size_t told = 0;
  render::CaptureOptions capture{.back_depth = true};
  if (ctx)
    capture.after_view = [&] {
      const std::size_t n = ++drawn_views;
      ctx->check_cancelled();
      if (std::this_thread::get_id() != job_thread || n < told + every) return;
      told = n;
      ctx->progress(0.4 * double(n) / double(cameras.size()), "rendering silhouettes");
    };
  const std::vector<render::ViewCapture> views =
      render::capture_cameras(renderer, drawn, cameras, out.contexts, capture);
  watch.stop(out.render_seconds, out.render_cpu_seconds);
  if (ctx) {
    ctx->check_cancelled();
    ctx->progress(0.4, "medial axes and votes");
  }
  {
    const render::ViewCapture& v = views[0];
    const std::vector<std::uint8_t> axis =
        medial_axis(chamfer_34(v.silhouette, p.image, p.image), p.image, p.image, p.min_radius);
    out.first_view.resize(axis.size());
    for (std::size_t i = 0; i < axis.size(); ++i) out.first_view[i] = axis[i] ? 2 : v.silhouette[i];
  }
  watch = Stopwatch{};  // restarted: the first view's medial axis (an artifact) is not a stage
  Votes votes = vote(views, box, p, ctx, 0.4, 0.75);
  out.votes = std::move(votes.grid);
  const std::vector<float>& radius = votes.radius;
  if (ctx) ctx->progress(0.75, "keeping votes inside the solid");
  const Solid solid = solid_future.get();
  // The loops the skeleton may have: the genus of a closed, oriented mesh
  // (its tunnels), found through the solid; other meshes: as the votes say.
  const MeshReport& report = solid.report;
  out.genus = report.closed && report.oriented && report.genus ? int(*report.genus) : -1;
  // A ray knows only where it enters the shape and where it leaves it, so
  // it votes across whatever lies between (the hole of a ring seen edge-on,
  // the gap between two arms): a closed mesh's votes are kept to its solid.
  if (solid.grid) {
    const VoxelGrid& g = *solid.grid;
    std::vector<float>& v = out.votes.floats();
    for (std::size_t n = 0; n < v.size(); ++n)
      if (v[n] > 0) {
        const VoxelIndex at = g.locate(out.votes.center(out.votes.unlinear(n)));
        if (!g.contains(at) || !g.bytes()[g.linear(at)]) v[n] = 0;
      }
  }
  watch.stop(out.vote_seconds, out.vote_cpu_seconds);
  if (ctx) ctx->progress(0.8, "thinning");
  const RayCaster& caster = *solid.caster;
  out.skeleton = thin(
      out.votes, radius, p, out.genus, [&](const Vec3& q) { return caster.inside(q); }, ctx, 0.8, 0.95);
  // Smoothing may not move a node out of the mesh.
  if (ctx) {
    ctx->check_cancelled();
    ctx->progress(0.95, "merging and smoothing");
  }
  simplify(out.skeleton, p.merge_distance * box.diagonal(), p.smoothing,
           [&](const Vec3& q) { return caster.inside(q); });
  // A node the votes put outside (a thin part, seen thicker than it is from
  // some views) moves towards a neighbour that is inside until it is too.
  if (ctx) ctx->progress(0.98, "moving nodes inside");
  Skeleton& s = out.skeleton;
  const Adjacency adj = skeleton_adjacency(s);
  std::vector<std::uint8_t> in(s.nodes.size());
  for (std::size_t n = 0; n < s.nodes.size(); ++n) in[n] = caster.inside(s.nodes[n]);
  for (int pass = 0; pass < 8; ++pass)
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      if (in[n]) continue;
      for (const std::uint32_t* m = adj.begin(n); m != adj.end(n) && !in[n]; ++m) {
        if (!in[*m]) continue;
        Vec3 q = s.nodes[n];
        for (int k = 0; k < 12 && !in[n]; ++k) {
          q = (q + s.nodes[*m]) * 0.5;
          if (caster.inside(q)) s.nodes[n] = q, in[n] = 1;
        }
      }
    }
  watch.stop(out.thin_seconds, out.thin_cpu_seconds);
  return out;
}

}  // namespace
}  // namespace skeleton

SkeletonProjectionResult skeleton_projection(const Mesh& mesh, const SkeletonProjectionParams& p, Context* context) {
  check_params(p);
  if (p.views % 2 != 0)
    throw InvalidInput("parameter 'views': " + std::to_string(p.views) + " must be an even number (antipodal pairs)");
  const Context& ctx = context_or_none(context);
  // The first context from the process's pool too (the others are, in
  // capture_cameras): a process that runs several jobs starts it once.
  render::RendererPool& pool = render::shared_pool(render::GlPlatform::automatic);
  std::unique_ptr<render::Renderer> renderer = pool.take();
  skeleton::Pipeline r;
  try {
    r = skeleton::run_stages(*renderer, mesh, p, &ctx);
  } catch (...) {
    pool.give_back(nullptr);  // given up with its context, as capture_cameras does
    throw;
  }
  pool.give_back(std::move(renderer));
  SkeletonProjectionResult out;
  out.metrics = metrics_table(measure_skeleton(r.skeleton, mesh));
  out.metrics["faces_drawn"] = double(r.faces_drawn);
  out.metrics["render_contexts"] = double(r.contexts);
  out.metrics["render_seconds"] = r.render_seconds;
  out.metrics["vote_seconds"] = r.vote_seconds;
  out.metrics["thin_seconds"] = r.thin_seconds;
  out.metrics["render_cpu_seconds"] = r.render_cpu_seconds;
  out.metrics["vote_cpu_seconds"] = r.vote_cpu_seconds;
  out.metrics["thin_cpu_seconds"] = r.thin_cpu_seconds;
  out.genus = r.genus;
  out.skeleton = std::move(r.skeleton);
  if (p.intermediate) {
    out.votes = std::move(r.votes);
    VoxelGrid view({p.image, p.image, 1}, Vec3{}, 1.0, VoxelType::uint8);
    for (int y = 0; y < p.image; ++y)  // rows from the bottom, as the grid's j
      for (int x = 0; x < p.image; ++x)
        view.set({x, p.image - 1 - y, 0}, float(r.first_view[std::size_t(y) * p.image + x]));
    out.first_view = std::move(view);
  }
  ctx.progress(1.0, "done");
  return out;
}

CGVIEW_REGISTER_FUNCTION(skeleton_projection, skeleton_projection,
                         {.title = "Skeleton from projections",
                          .description = "The paper's curve skeleton: medial axes of silhouettes rendered from many "
                                         "views vote in a voxel grid, thinned along the ridge of votes, merged and "
                                         "smoothed.",
                          .area = "skeleton"})

}  // namespace cgview
