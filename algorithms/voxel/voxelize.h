// voxelize: the voxels a triangle mesh's surface touches, or the solid it
// encloses, on a grid of a given resolution or voxel size.
//
// Surface: voxel v is marked when the triangle meets v's open cube after an
// infinitesimal shift of the triangle against its normal (towards the
// inside of an outward-oriented mesh).  The test is the separating-axis
// triangle-box overlap of Akenine-Moller ("Fast 3D triangle-box overlap
// testing", JGT 2001: the 3 box axes, the triangle's normal and the 9 edge
// cross products), with ties on the 3 box axes broken by the sign of the
// normal's component (on the 10 others a tie, or a near tie within rounding,
// counts as overlap: a voxel too many rather than a gap).
// So:
//   - no gaps: the closed marked voxels cover the surface, so a connected
//     surface gives a 26-connected set whatever the size, thinness or slant
//     of its triangles (a triangle smaller than a voxel marks its voxel);
//   - a face lying exactly on a voxel boundary marks the voxel behind it, and
//     an edge lying on one marks nothing more: an axis-aligned box whose sides
//     fall on voxel boundaries gives exactly the voxels inside it.
//   Degenerate (zero-area) triangles mark nothing.
// Solid: the surface voxels plus every empty voxel that a 6-connected flood
// of empty voxels from the grid's border does not reach.  Since the marked
// voxels cover the surface, a closed mesh's solid covers its whole volume
// (the solid's volume is never below the mesh's).  A mesh that is not closed
// gets a warning with its number of boundary loops; holes narrower than a
// voxel are closed by the surface voxels, wider ones let the flood in.
//
// A point cloud (a mesh with no faces, as files hold one): in surface mode
// each point marks the voxel holding it (voxel v is the half-open cube, a
// point on the box's far side marks the last voxel inside the padding);
// solid mode refuses it, having no inside.
//
// Grid: origin = bounding-box minimum - padding * voxel_size;
// dims[a] = ceil(extent[a] / voxel_size) + 2 * padding (at least 1 + 2 * padding);
// voxel_size = longest extent / resolution unless voxel_size > 0 is given.
// Storage: VoxelType::bit, one byte per voxel (core/voxel_grid.h).
//
// The grid is an artifact ("grid") that can be saved as .binvox, .raw (with
// a .json sidecar), .nrrd, .vti, .vox, .vdb or .vtk.
//
//   Mesh m = read_mesh("elephant.off");
//   VoxelizeResult r = voxelize(m, {.resolution = 64, .mode = VoxelizeMode::surface});
//   write_voxel_grid(r.grid, "elephant.nrrd");
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/voxel_grid.h"
#include "registry/registry.h"

namespace cgview {

enum class VoxelizeMode { surface, solid };

// The grid's size and its memory limit, as every algorithm that voxelizes
// (voxelize, voxel_surface, voxel_distance) takes them: described once.
// `most`: the largest resolution it allows; `per_voxel`: what its help says a
// voxel costs.
template <class V>
void describe_resolution(V& v, int& resolution, double most = 8192) {
  v.integer(
      "resolution", resolution,
      {.label = "Resolution", .min = 1, .max = most, .help = "voxels along the longest side of the bounding box"});
}
template <class V>
void describe_memory_limit(V& v, double& max_memory_mb, const char* per_voxel = "1 byte per voxel") {
  v.number("max_memory_mb", max_memory_mb,
           {.label = "Memory limit (MB)",
            .min = 1,
            .max = 1e6,
            .help = "refuse a grid that needs more memory (" + std::string(per_voxel) + ")",
            .advanced = true});
}

struct VoxelizeParams {
  int resolution = 128;     // voxels along the longest side of the bounding box
  double voxel_size = 0.0;  // > 0: use this size and ignore resolution
  VoxelizeMode mode = VoxelizeMode::solid;
  int padding = 1;              // empty voxels added on every side
  double max_memory_mb = 2048;  // refuse grids that would need more
  // Not parameters of a job (describe leaves them out): what a caller in
  // C++ may set besides.
  int threads = 0;  // 0: every core (thread_count())
  // The box the grid covers (with the padding around it), when it must match
  // another grid's; it must hold the faces.  Default: the faces' own box.
  std::optional<BBox> box{};
  template <class V>
  void describe(V& v) {
    describe_resolution(v, resolution);
    v.number("voxel_size", voxel_size,
             {.label = "Voxel size", .min = 0, .help = "edge of a voxel in mesh units; 0: from the resolution"});
    v.choice("mode", mode,
             {.label = "Mode",
              .help = "surface: the voxels the surface touches (exact triangle-box test); solid: those plus the "
                      "interior (flood fill of the outside from the grid's border)",
              .choices = {"surface", "solid"}});
    v.integer("padding", padding, {.label = "Padding", .min = 0, .max = 64, .help = "empty voxels added on each side"});
    describe_memory_limit(v, max_memory_mb);
  }
};

struct VoxelizeResult {
  VoxelGrid grid;  // bit grid, 1 = occupied
  // dim_x, dim_y, dim_z, voxel_size, surface_voxels, occupied_voxels,
  // occupied_volume, memory_mb; boundary_loops in solid mode
  Metrics metrics;
  std::size_t surface_voxels = 0;  // voxels the surface touches
  std::size_t solid_voxels = 0;    // surface + interior (solid mode; = surface_voxels otherwise)
  std::size_t boundary_loops = 0;  // of the mesh (0 for a closed mesh)
  std::size_t boundary_edges = 0;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("grid", grid);
    v("metrics", metrics);
  }
};

// Throws InvalidInput for a parameter outside its range (check_params), an
// empty or invalid mesh, a point cloud in solid mode, a given box that does
// not hold the faces (a cloud's points), and a grid whose memory (one byte
// per voxel) would pass max_memory_mb: the message says how much it would
// take.  ctx (optional): progress and cancellation
// (throws Cancelled); a const one, so that a thread of another job
// (skeleton_projection's solid) may pass its own.
VoxelizeResult voxelize(const Mesh& mesh, const VoxelizeParams& p = {}, Context* ctx = nullptr);

// voxelize without check_params and without the metrics
// (voxel/voxelization.cpp), for an algorithm that voxelizes on its way with
// parameters it derives: voxel_distance's memory limit is 1/13 of its own,
// under voxelize's minimum of 1 MB.  The caller keeps the other values in
// their ranges.
VoxelizeResult voxelize_unchecked(const Mesh& mesh, const VoxelizeParams& p, const Context* ctx = nullptr);

// Memory (bytes) a grid of these dimensions needs while voxelizing.
double voxelize_memory_bytes(std::array<int, 3> dims);

// The grid voxelize would make for a bounding box: its dimensions, voxel size
// and memory (bytes).  Throws InvalidInput as voxelize does for a grid over
// max_memory_mb (without allocating anything); the parameters are checked
// by the caller.
struct VoxelizeGeometry {
  std::array<int, 3> dims;
  double voxel_size;
  double memory_bytes;
};
VoxelizeGeometry voxelize_geometry(const BBox& box, const VoxelizeParams& params);

// The surface voxels of one triangle (a, b, c given in grid coordinates,
// where voxel (i, j, k) is the unit cube [i, i+1) x [j, j+1) x [k, k+1)),
// each passed to f(i, j, k); clipped to [0, dims).  Exposed for tests.
template <class F>
void for_each_triangle_voxel(const Vec3& a, const Vec3& b, const Vec3& c, std::array<int, 3> dims, F&& f);

}  // namespace cgview

#include "voxel/voxelize_impl.h"
