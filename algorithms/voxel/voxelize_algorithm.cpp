// voxelize, registered: surface or solid voxels of a mesh (voxel/voxelize.h).
// The grid is an artifact ("grid") that can be saved as .binvox, .raw (with
// a .json sidecar), .nrrd, .vti, .vox, .vdb or .vtk.
#include <string>

#include "registry/registry.h"
#include "voxel/voxelize.h"

namespace cgview {
namespace {

struct Params {
  int resolution = 128;
  double voxel_size = 0.0;
  std::string mode = "solid";
  int padding = 1;
  double max_memory_mb = 2048;
  template <class V>
  void describe(V& v) {
    v.integer(
        "resolution", resolution,
        {.label = "Resolution", .min = 1, .max = 8192, .help = "voxels along the longest side of the bounding box"});
    v.number("voxel_size", voxel_size,
             {.label = "Voxel size", .min = 0, .help = "edge of a voxel in mesh units; 0: from the resolution"});
    v.choice("mode", mode,
             {.label = "Mode",
              .help = "surface: the voxels the surface touches (exact triangle-box test); solid: those plus the "
                      "interior (flood fill of the outside from the grid's border)",
              .choices = {"surface", "solid"}});
    v.integer("padding", padding, {.label = "Padding", .min = 0, .max = 64, .help = "empty voxels added on each side"});
    v.number("max_memory_mb", max_memory_mb,
             {.label = "Memory limit (MB)",
              .min = 1,
              .max = 1e6,
              .help = "refuse a grid that needs more memory (1 byte per voxel)",
              .advanced = true});
  }
};

VoxelizeParams voxelize_params(const Params& p) {
  VoxelizeParams vp;
  vp.resolution = p.resolution;
  vp.voxel_size = p.voxel_size;
  vp.mode = parse_voxelize_mode(p.mode);
  vp.padding = p.padding;
  vp.max_memory_mb = p.max_memory_mb;
  return vp;
}

// Before the job runs: the grid for the mesh's bounding box must fit the
// memory limit (the server answers 400 with what it would take).  The stored
// box spans every vertex, voxelize's only those faces use: never smaller.
void precheck(const InputSummaries& in, const Params& p) {
  const auto it = in.find("mesh");
  if (it != in.end() && !it->second.bbox.empty()) (void)voxelize_geometry(it->second.bbox, voxelize_params(p));
}

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  const VoxelizeParams vp = voxelize_params(p);
  VoxelizeResult r = voxelize(mesh, vp, &ctx);
  const auto d = r.grid.dims();
  const double s = r.grid.voxel_size();
  Metrics m{{"dim_x", double(d[0])},
            {"dim_y", double(d[1])},
            {"dim_z", double(d[2])},
            {"voxel_size", s},
            {"surface_voxels", double(r.surface_voxels)},
            {"occupied_voxels", double(r.solid_voxels)},
            {"occupied_volume", double(r.solid_voxels) * s * s * s},
            {"memory_mb", double(r.grid.size()) / (1024.0 * 1024.0)}};
  if (vp.mode == VoxelizeMode::solid) m["boundary_loops"] = double(r.boundary_loops);
  AlgorithmResult result;
  result.artifacts.push_back({"grid", std::move(r.grid)});
  result.artifacts.push_back({"metrics", std::move(m)});
  result.warnings = std::move(r.warnings);
  return result;
}

CGVIEW_REGISTER_ALGORITHM(voxelize, Params, run,
                          {.title = "Voxelize",
                           .description = "Surface or solid voxels of the mesh at a resolution or voxel size: exact "
                                          "triangle-box overlap (no gaps), interior by a flood fill of the outside.",
                           .area = "voxel",
                           .outputs = {{"grid", OutputKind::voxel_grid}, {"metrics", OutputKind::metrics}}})
CGVIEW_REGISTER_PRECHECK(voxelize, Params, precheck)

}  // namespace
}  // namespace cgview
