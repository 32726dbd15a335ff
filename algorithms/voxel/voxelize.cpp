#include "voxel/voxelize.h"

#include <string>

namespace cgview {
namespace {

// Before the job runs: the grid for the mesh's bounding box must fit the
// memory limit (the server answers 400 with what it would take).  The stored
// box spans every vertex, voxelize's only those faces use: never smaller.
void precheck(const InputSummaries& in, const VoxelizeParams& p) {
  const auto it = in.find("mesh");
  if (it != in.end() && !it->second.bbox.empty()) (void)voxelize_geometry(it->second.bbox, p);
}

}  // namespace

VoxelizeResult voxelize(const Mesh& mesh, const VoxelizeParams& p, Context* ctx) {
  check_params(p);
  VoxelizeResult r = voxelize_unchecked(mesh, p, ctx);
  const auto d = r.grid.dims();
  const double s = r.grid.voxel_size();
  r.metrics = {{"dim_x", double(d[0])},
               {"dim_y", double(d[1])},
               {"dim_z", double(d[2])},
               {"voxel_size", s},
               {"surface_voxels", double(r.surface_voxels)},
               {"occupied_voxels", double(r.solid_voxels)},
               {"occupied_volume", double(r.solid_voxels) * s * s * s},
               {"memory_mb", double(r.grid.size()) / (1024.0 * 1024.0)}};
  if (p.mode == VoxelizeMode::solid) r.metrics["boundary_loops"] = double(r.boundary_loops);
  return r;
}

// voxelize takes a const Context (see voxelize.h), the registry a function
// of a Context*: a lambda adapts it.
CGVIEW_REGISTER_FUNCTION(
    voxelize, voxelize,
    {.title = "Voxelize",
     .description =
         "Surface or solid voxels of the mesh at a resolution or voxel size: exact "
         "triangle-box overlap (no gaps), interior by a flood fill of the outside; a point cloud (no faces): "
         "the voxels holding its points, in surface mode.",
     .area = "voxel",
     .inputs = {{.name = "mesh",
                 .kind = OutputKind::mesh,
                 .help = "the mesh to voxelize, or a point cloud (surface mode)",
                 .faceless = true}}})
CGVIEW_REGISTER_PRECHECK(voxelize, VoxelizeParams, precheck)

}  // namespace cgview
