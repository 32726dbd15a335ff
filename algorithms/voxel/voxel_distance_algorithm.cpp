// voxel_distance, registered: a scalar grid (a float per voxel), the
// Euclidean distance from each solid voxel to the outside (voxelize, then
// distance_transform): the medial "depth" of the shape, which the viewer shows
// in slices with a threshold slider.
#include <string>

#include "registry/registry.h"
#include "voxel/voxel_ops.h"
#include "voxel/voxelize.h"

namespace cgview {
namespace {

struct Params {
  int resolution = 64;
  double max_memory_mb = 2048;
  template <class V>
  void describe(V& v) {
    v.integer(
        "resolution", resolution,
        {.label = "Resolution", .min = 1, .max = 4096, .help = "voxels along the longest side of the bounding box"});
    v.number("max_memory_mb", max_memory_mb,
             {.label = "Memory limit (MB)",
              .min = 1,
              .max = 1e6,
              .help = "refuse a grid that needs more memory (1 byte per voxel, and 12 more for the distances)",
              .advanced = true});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  VoxelizeParams vp;
  vp.resolution = p.resolution;
  vp.mode = VoxelizeMode::solid;
  // The distances take a float and a double per voxel besides the grid's byte.
  vp.max_memory_mb = p.max_memory_mb / 13.0;
  VoxelizeResult r;
  try {
    r = voxelize(mesh, vp, &ctx);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string(e.what()) +
                       " (voxel_distance needs 13 bytes per voxel: 1/13 of max_memory_mb for the grid)");
  }
  ctx.check_cancelled();
  ctx.progress(0.8, "distance transform");
  VoxelGrid depth = distance_transform(r.grid, {.inside = true});
  const auto [lo, hi] = value_range(depth);
  AlgorithmResult result;
  result.artifacts.push_back({"distance", std::move(depth)});
  result.artifacts.push_back({"metrics", Metrics{{"max_distance", double(hi)},
                                                 {"min_distance", double(lo)},
                                                 {"voxel_size", r.grid.voxel_size()},
                                                 {"voxels", double(r.solid_voxels)}}});
  result.warnings = std::move(r.warnings);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(voxel_distance, Params, run,
                          {.title = "Voxel distance to the outside",
                           .description = "A scalar grid: for each voxel of the solid, the Euclidean distance to the "
                                          "nearest voxel outside it (exact distance transform).",
                           .area = "voxel",
                           .outputs = {{"distance", OutputKind::voxel_grid}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
