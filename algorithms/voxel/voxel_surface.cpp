#include "voxel/voxel_surface.h"

#include "voxel/voxel_ops.h"

namespace cgview {

VoxelSurfaceResult voxel_surface(const Mesh& mesh, const VoxelSurfaceParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  VoxelizeResult r =
      voxelize(mesh, {.resolution = p.resolution, .mode = p.mode, .max_memory_mb = p.max_memory_mb}, context);
  ctx.check_cancelled();
  ctx.progress(0.9, "boundary");
  VoxelSurfaceResult result;
  result.mesh = boundary_mesh(r.grid);
  const double s = r.grid.voxel_size();
  result.metrics = {{"voxels", double(r.solid_voxels)},
                    {"voxel_size", s},
                    {"triangles", double(result.mesh.num_faces())},
                    {"volume", double(r.solid_voxels) * s * s * s}};
  result.warnings = std::move(r.warnings);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(voxel_surface, voxel_surface,
                         {.title = "Voxel surface",
                          .description = "The boundary of the mesh's voxels as a mesh, coplanar voxel faces merged "
                                         "into rectangles: how the voxelization looks.",
                          .area = "voxel"})

}  // namespace cgview
