// grid_surface, registered: the boundary of an earlier job's voxel grid as a
// mesh, coplanar voxel faces merged (boundary_mesh), after a threshold for
// scalar grids (voxel_distance's distances, a skeleton's vote grid).  Its
// input is a grid, not a mesh: a job names it {"job": ID, "artifact": "grid"},
// `cgview run grid_surface e.nrrd` reads it from a file.
#include <string>

#include "registry/registry.h"
#include "voxel/voxel_ops.h"

namespace cgview {
namespace {

struct Params {
  double threshold = 0;
  template <class V>
  void describe(V& v) {
    v.number("threshold", threshold,
             {.label = "Threshold",
              .min = -1e30,
              .max = 1e30,
              .help = "the voxels whose value is above it (occupancy grids: 0 keeps every occupied voxel)"});
  }
};

AlgorithmResult run(const Inputs& in, const Params& p, Context& ctx) {
  const VoxelGrid& grid = in.voxel_grid("grid");
  ctx.progress(0, "threshold");
  const VoxelGrid kept = threshold(grid, float(p.threshold));
  ctx.check_cancelled();
  ctx.progress(0.3, "boundary");
  Mesh surface = boundary_mesh(kept);
  const double s = kept.voxel_size();
  const std::size_t voxels = kept.count_occupied();
  AlgorithmResult result;
  if (voxels == 0) result.warnings.push_back("no voxel is above the threshold: the surface is empty");
  result.artifacts.push_back({"mesh", std::move(surface)});
  result.artifacts.push_back(
      {"metrics", Metrics{{"voxels", double(voxels)}, {"voxel_size", s}, {"volume", double(voxels) * s * s * s}}});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(grid_surface, Params, run,
                          {.title = "Voxel grid surface",
                           .description = "The boundary of a voxel grid (an earlier job's grid: voxelize, "
                                          "voxel_distance) as a mesh, after a threshold, coplanar faces merged.",
                           .area = "voxel",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}},
                           .inputs = {{.name = "grid", .kind = OutputKind::voxel_grid, .help = "the voxel grid"}}})

}  // namespace
}  // namespace cgview
