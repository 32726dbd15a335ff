#include "voxel/voxel_distance.h"

#include <string>

#include "voxel/voxel_ops.h"
#include "voxel/voxelize.h"

namespace cgview {

VoxelDistanceResult voxel_distance(const Mesh& mesh, const VoxelDistanceParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  VoxelizeParams vp;
  vp.resolution = p.resolution;
  vp.mode = VoxelizeMode::solid;
  // The distances take a float and a double per voxel besides the grid's
  // byte.  The limit may fall under voxelize's minimum of 1 MB: unchecked.
  vp.max_memory_mb = p.max_memory_mb / 13.0;
  VoxelizeResult r;
  try {
    r = voxelize_unchecked(mesh, vp, &ctx);
  } catch (const InvalidInput& e) {
    throw InvalidInput(std::string(e.what()) +
                       " (voxel_distance needs 13 bytes per voxel: 1/13 of max_memory_mb for the grid)");
  }
  ctx.check_cancelled();
  ctx.progress(0.8, "distance transform");
  VoxelDistanceResult result;
  result.distance = distance_transform(r.grid, {.inside = true});
  const auto [lo, hi] = value_range(result.distance);
  result.metrics = {{"max_distance", double(hi)},
                    {"min_distance", double(lo)},
                    {"voxel_size", r.grid.voxel_size()},
                    {"voxels", double(r.solid_voxels)}};
  result.warnings = std::move(r.warnings);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(voxel_distance, voxel_distance,
                         {.title = "Voxel distance to the outside",
                          .description = "A scalar grid: for each voxel of the solid, the Euclidean distance to the "
                                         "nearest voxel outside it (exact distance transform).",
                          .area = "voxel"})

}  // namespace cgview
