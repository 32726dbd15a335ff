#include "voxel/grid_surface.h"

#include "voxel/voxel_ops.h"

namespace cgview {

GridSurfaceResult grid_surface(const VoxelGrid& grid, const GridSurfaceParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0, "threshold");
  const VoxelGrid kept = threshold(grid, float(p.threshold));
  ctx.check_cancelled();
  ctx.progress(0.3, "boundary");
  GridSurfaceResult result;
  result.mesh = boundary_mesh(kept);
  const double s = kept.voxel_size();
  const std::size_t voxels = kept.count_occupied();
  if (voxels == 0) result.warnings.push_back("no voxel is above the threshold: the surface is empty");
  result.metrics = {{"voxels", double(voxels)}, {"voxel_size", s}, {"volume", double(voxels) * s * s * s}};
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(grid_surface,
                         [](const Inputs& in, const GridSurfaceParams& p, Context* c) {
                           return grid_surface(in.voxel_grid("grid"), p, c);
                         },
                         {.title = "Voxel grid surface",
                          .description = "The boundary of a voxel grid (an earlier job's grid: voxelize, "
                                         "voxel_distance) as a mesh, after a threshold, coplanar faces merged.",
                          .area = "voxel",
                          .inputs = {{.name = "grid", .kind = OutputKind::voxel_grid, .help = "the voxel grid"}}})

}  // namespace cgview
