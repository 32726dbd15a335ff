// Voxelization: CGView's solid voxelization against OpenVDB's
// meshToLevelSet plus sdfInteriorMask (the narrow-band level set, its sign
// flood fill, and the interior as a mask) at the same voxel size and the same
// voxel centres, with the agreement of the two; and CGView's surface
// voxelization throughput.  Meshes: refined_elephant (the largest sample,
// 89k triangles, closed) and refined_elephant subdivided twice (1.42M
// triangles).  Both sides use every core (OpenVDB through TBB, CGView through
// std::thread).  Prints a Markdown table.
//
//   build/bin/voxel_bench [--quick] [--max-res N] [--repeat N] [--res N]... [--large-only] [--no-openvdb] [--threads N]
#include <openvdb/openvdb.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "io/mesh_io.h"
#include "io/samples.h"
#include "voxel/voxelize.h"

using namespace cgview;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double best_seconds(int repeat, const std::function<void()>& f) {
  double best = 1e300;
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, seconds_since(t0));
  }
  return best;
}

struct Input {
  std::string name;
  Mesh mesh;
};

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, large_only = false, no_vdb = false;
  int threads = 0;  // 0: all cores
  int max_res = 1024, repeat = 2;
  std::vector<int> only_res;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--max-res" && i + 1 < argc) max_res = std::atoi(argv[++i]);
    else if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--res" && i + 1 < argc) only_res.push_back(std::atoi(argv[++i]));
    else if (a == "--large-only") large_only = true;
    else if (a == "--no-openvdb") no_vdb = true;
    else if (a == "--threads" && i + 1 < argc) threads = std::max(1, std::atoi(argv[++i]));
    else {
      std::fprintf(stderr,
                   "usage: voxel_bench [--quick] [--max-res N] [--repeat N] [--res N]... [--large-only] [--no-openvdb] "
                   "[--threads N]\n");
      return 2;
    }
  }
  openvdb::initialize();
  // The same number of threads on both sides: TBB's limit for OpenVDB.
  const unsigned nthreads = threads > 0 ? unsigned(threads) : std::thread::hardware_concurrency();
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, nthreads);
  const auto path = resolve_mesh_path("refined_elephant.off");
  if (!path) {
    std::fprintf(stderr, "voxel_bench: refined_elephant.off not found (install libcgal-demo, re-run cmake)\n");
    return 1;
  }
  std::vector<Input> inputs;
  inputs.push_back({"refined_elephant", read_mesh(*path)});
  if (!quick)
    inputs.push_back({"refined_elephant subdivided twice", subdivide_midpoint(subdivide_midpoint(inputs[0].mesh))});
  std::vector<int> resolutions = quick ? std::vector<int>{128, 256} : std::vector<int>{128, 256, 512, 1024};
  if (!only_res.empty()) resolutions = only_res;
  if (large_only && inputs.size() > 1) inputs.erase(inputs.begin());
  resolutions.erase(std::remove_if(resolutions.begin(), resolutions.end(), [&](int r) { return r > max_res; }),
                    resolutions.end());

  std::printf("threads: %u (both sides)\n\n", nthreads);
  std::printf(
      "| mesh | triangles | resolution | grid | CGView solid s | OpenVDB solid s (of which meshToLevelSet) | OpenVDB / "
      "CGView | "
      "CGView surface s | surface Mtri/s | dense grid alone s | surface Mtri/s without it | voxels inside: CGView | "
      "OpenVDB | "
      "OpenVDB's inside also CGView's | CGView's inside also OpenVDB's |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Input& in : inputs) {
    std::vector<openvdb::Vec3s> points;
    points.reserve(in.mesh.num_vertices());
    for (const Vec3& p : in.mesh.positions) points.emplace_back(float(p.x), float(p.y), float(p.z));
    std::vector<openvdb::Vec3I> tris;
    tris.reserve(in.mesh.num_faces());
    for (const Tri& t : in.mesh.faces) tris.emplace_back(t[0], t[1], t[2]);

    for (int res : resolutions) {
      const int rep = res >= 512 ? 1 : repeat;
      VoxelizeParams p;
      p.resolution = res;
      p.max_memory_mb = 8192;
      p.threads = int(nthreads);
      p.mode = VoxelizeMode::surface;
      std::array<int, 3> surface_dims{};
      const double t_surface = best_seconds(rep, [&] { surface_dims = voxelize(in.mesh, p).grid.dims(); });
      // The dense grid's own cost (allocate, clear, count: 1 byte a voxel),
      // which every run above pays besides its triangles.
      std::size_t sink = 0;
      const double t_grid = best_seconds(rep, [&] {
        VoxelGrid g(surface_dims, {0, 0, 0}, 1.0, VoxelType::bit, std::uint64_t(1) << 40);
        sink += g.count_occupied();
      });
      if (sink == 1) std::printf(" ");
      p.mode = VoxelizeMode::solid;
      VoxelizeResult ours;
      const double t_solid = best_seconds(rep, [&] { ours = voxelize(in.mesh, p); });

      // OpenVDB at the same voxel size; index (i, j, k) at CGView's voxel centre.
      const double s = ours.grid.voxel_size();
      const Vec3 c = ours.grid.origin() + Vec3{0.5, 0.5, 0.5} * s;
      auto xf = openvdb::math::Transform::createLinearTransform(s);
      xf->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
      openvdb::FloatGrid::Ptr sdf;
      openvdb::BoolGrid::Ptr interior;
      if (no_vdb) {
        std::printf("| %s | %zu | %d | CGView only | %.3f | | | %.3f | %.1f | %.3f | %.1f | %zu | | | |\n",
                    in.name.c_str(), in.mesh.num_faces(), res, t_solid, t_surface,
                    double(in.mesh.num_faces()) / t_surface / 1e6, t_grid,
                    double(in.mesh.num_faces()) / std::max(1e-6, t_surface - t_grid) / 1e6, ours.solid_voxels);
        continue;
      }
      double t_ls = 1e300;
      const double t_vdb = best_seconds(rep, [&] {
        const auto t0 = std::chrono::steady_clock::now();
        sdf = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xf, points, tris, 3.0f);
        t_ls = std::min(t_ls, seconds_since(t0));
        interior = openvdb::tools::sdfInteriorMask(*sdf);
      });

      // Agreement at the voxel centres: OpenVDB inside = sdf < 0 there; CGView
      // inside = occupied (conservative: every voxel the surface touches too).
      // At 1024 every 2nd voxel along each axis is compared (1/8 of them).
      const int step = res >= 1024 ? 2 : 1;
      const auto d = ours.grid.dims();
      std::size_t both = 0, vdb_in = 0, ours_in = 0;
      auto acc = interior->getConstAccessor();
      for (int k = 0; k < d[2]; k += step)
        for (int j = 0; j < d[1]; j += step)
          for (int i = 0; i < d[0]; i += step) {
            const bool o = ours.grid.bytes()[ours.grid.linear({i, j, k})] != 0;
            const bool v = acc.isValueOn(openvdb::Coord(i, j, k));
            ours_in += o;
            vdb_in += v;
            both += o && v;
          }
      std::printf(
          "| %s | %zu | %d | %dx%dx%d | %.3f | %.3f (%.3f) | %.2f | %.3f | %.1f | %.3f | %.1f | %zu | %zu | %.4f%% | "
          "%.2f%% |\n",
          in.name.c_str(), in.mesh.num_faces(), res, d[0], d[1], d[2], t_solid, t_vdb, t_ls, t_vdb / t_solid, t_surface,
          double(in.mesh.num_faces()) / t_surface / 1e6, t_grid,
          double(in.mesh.num_faces()) / std::max(1e-6, t_surface - t_grid) / 1e6,
          ours_in * std::size_t(step * step * step), vdb_in * std::size_t(step * step * step),
          100.0 * double(both) / double(std::max<std::size_t>(vdb_in, 1)),
          100.0 * double(both) / double(std::max<std::size_t>(ours_in, 1)));
      std::fflush(stdout);
    }
  }
  return 0;
}
