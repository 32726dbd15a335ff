// voxel_surface, registered: the boundary of a mesh's voxels as a mesh
// (voxelize, then boundary_mesh with coplanar faces merged), so that the
// viewer shows the voxel surface as it shows any mesh artifact.
#include <string>

#include "registry/registry.h"
#include "voxel/voxel_ops.h"
#include "voxel/voxelize.h"

namespace cgview {
namespace {

struct Params {
  int resolution = 64;
  std::string mode = "solid";
  double max_memory_mb = 2048;
  template <class V>
  void describe(V& v) {
    v.integer(
        "resolution", resolution,
        {.label = "Resolution", .min = 1, .max = 8192, .help = "voxels along the longest side of the bounding box"});
    v.choice(
        "mode", mode,
        {.label = "Mode",
         .help = "solid: the outer surface of the solid voxels; surface: both sides of the shell of surface voxels",
         .choices = {"surface", "solid"}});
    v.number("max_memory_mb", max_memory_mb,
             {.label = "Memory limit (MB)",
              .min = 1,
              .max = 1e6,
              .help = "refuse a grid that needs more memory (1 byte per voxel)",
              .advanced = true});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  VoxelizeParams vp;
  vp.resolution = p.resolution;
  vp.mode = parse_voxelize_mode(p.mode);
  vp.max_memory_mb = p.max_memory_mb;
  VoxelizeResult r = voxelize(mesh, vp, &ctx);
  ctx.check_cancelled();
  ctx.progress(0.9, "boundary");
  Mesh surface = boundary_mesh(r.grid);
  const double s = r.grid.voxel_size();
  Metrics m{{"voxels", double(r.solid_voxels)},
            {"voxel_size", s},
            {"triangles", double(surface.num_faces())},
            {"volume", double(r.solid_voxels) * s * s * s}};
  AlgorithmResult result;
  result.artifacts.push_back({"mesh", std::move(surface)});
  result.artifacts.push_back({"metrics", std::move(m)});
  result.warnings = std::move(r.warnings);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(voxel_surface, Params, run,
                          {.title = "Voxel surface",
                           .description = "The boundary of the mesh's voxels as a mesh, coplanar voxel faces merged "
                                          "into rectangles: how the voxelization looks.",
                           .area = "voxel",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
