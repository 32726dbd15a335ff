#include "skeleton/projection/vote.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "core/threads.h"
#include "registry/registry.h"
#include "render/renderer.h"
#include "render/views.h"
#include "skeleton/projection/medial_axis.h"

namespace cgview::skeleton {

double vote_voxel_size(const BBox& box, int grid) {
  const Vec3 size = box.size();
  return std::max({size.x, size.y, size.z, 1e-12}) / grid;
}

Votes vote(const std::vector<render::ViewCapture>& views, const BBox& box, const SkeletonProjectionParams& p,
           const Context* ctx, double progress_from, double progress_to) {
  for (const render::ViewCapture& v : views)
    if (v.back_depth.size() != v.depth.size()) throw InvalidInput("vote: every view needs its back depth");
  const Vec3 size = box.size();
  const double vs = vote_voxel_size(box, p.grid);
  const std::array<int, 3> dims{int(std::ceil(size.x / vs)) + 2, int(std::ceil(size.y / vs)) + 2,
                                int(std::ceil(size.z / vs)) + 2};
  const Vec3 origin = box.min - Vec3{vs, vs, vs};
  VoxelGrid grid(dims, origin, vs, VoxelType::float32);
  const int threads = std::max(1, std::min(thread_count(), int(views.size())));
  // Each thread votes into a grid of its own, a voxel's votes beside the
  // sum of their radii (a ray's samples are far apart in memory: one cache
  // line for both), added after.
  std::vector<std::vector<std::array<float, 2>>> partial(threads);
  // The job's progress is the calling thread's: the thread on which
  // on_threads runs t = 0 (core/threads.h).  Its share of the views is done
  // at the pace of the others', so its count tells the whole; about 20
  // reports.
  const std::size_t share = (views.size() + std::size_t(threads) - 1) / std::size_t(threads);
  const std::size_t every = std::max<std::size_t>(1, share / 20);
  auto work = [&](int t) {
    std::vector<std::array<float, 2>>& acc = partial[t];
    acc.assign(grid.size(), {0.f, 0.f});
    for (std::size_t v = std::size_t(t), k = 0; v < views.size(); v += std::size_t(threads), ++k) {
      if (t == 0 && ctx) {
        if (ctx->cancelled()) return;
        if (k % every == 0 && k > 0)
          ctx->progress(progress_from + (progress_to - progress_from) * double(v) / double(views.size()),
                        "medial axes and votes");
      }
      const render::ViewCapture& view = views[v];
      const int w = view.camera.width, h = view.camera.height;
      const std::vector<std::uint16_t> dt = chamfer_34(view.silhouette, w, h);
      const std::vector<std::uint8_t> axis = medial_axis(dt, w, h, p.min_radius);
      const Vec3 dir = view.camera.forward();
      const double pixel = view.camera.pixel_size_at(0);
      // The camera's matrix inverted once per view (unproject would invert it
      // at every pixel).
      const render::Mat4 from_view = render::inverse(view.camera.view_projection());
      const auto unproject = [&](double x, double y, float depth) {
        return render::transform_point(from_view, Vec3{2 * x / w - 1, 1 - 2 * y / h, 2 * double(depth) - 1});
      };
      // The ray's samples, every half voxel, in voxel units from the grid's origin.
      const Vec3 half_step = dir * 0.5;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          const std::size_t i = std::size_t(y) * w + x;
          if (!axis[i] || view.depth[i] >= 1.f) continue;
          const Vec3 entry = unproject(x + 0.5, y + 0.5, view.depth[i]);
          const Vec3 exit = unproject(x + 0.5, y + 0.5, view.back_depth[i]);
          const double radius_world = dt[i] / 3.0 * pixel;
          const double length = std::min(2 * radius_world, std::max(0.0, dot(exit - entry, dir)));
          const int samples = int(std::floor(length / (vs / 2))) + 1;
          // The ray votes from where it enters, and (as the antipodal view's
          // ray) back from where it leaves: where it crosses the shape twice,
          // both parts it crosses.
          for (const auto& [from, step] : {std::pair{entry, half_step}, std::pair{exit, half_step * -1.0}}) {
            // A straight ray leaves a voxel for good: a sample in the voxel of
            // the one before is the same vote.
            std::size_t last = SIZE_MAX;
            Vec3 g = (from - origin) / vs;
            for (int k = 0; k < samples; ++k, g += step) {
              const double fx = std::floor(g.x), fy = std::floor(g.y), fz = std::floor(g.z);
              if (!(fx >= 0 && fy >= 0 && fz >= 0 && fx < dims[0] && fy < dims[1] && fz < dims[2])) continue;
              const std::size_t n =
                  std::size_t(fx) + std::size_t(dims[0]) * (std::size_t(fy) + std::size_t(dims[1]) * std::size_t(fz));
              if (n == last) continue;
              last = n;
              acc[n][0] += 1.f;
              acc[n][1] += float(radius_world);
            }
          }
        }
    }
  };
  on_threads(threads, work);
  if (ctx) ctx->check_cancelled();
  // The threads' grids added up, a range of voxels each.
  std::vector<float>& out = grid.floats();
  std::vector<float> radius(grid.size(), 0.f);
  on_threads(threads, [&](int t) {
    const std::size_t a = grid.size() * std::size_t(t) / std::size_t(threads);
    const std::size_t b = grid.size() * std::size_t(t + 1) / std::size_t(threads);
    for (std::size_t n = a; n < b; ++n) {
      float v = 0, r = 0;
      for (const auto& part : partial) v += part[n][0], r += part[n][1];
      out[n] = v;
      radius[n] = v > 0 ? r / v : 0.f;
    }
  });
  return {std::move(grid), std::move(radius)};
}

}  // namespace cgview::skeleton
