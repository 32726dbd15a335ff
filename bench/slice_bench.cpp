// Paging through a voxel grid's slices over the WebSocket handler: each
// slice read from the grid's file and decoded (what every slice cost before
// decoded grids were kept), against the grid kept decoded after the first.
// The handler's replies are made in full (the zlib payload and its frames);
// no sockets.  Usage: slice_bench [--repeat N] [--quick]
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench_util.h"
#include "core/voxel_grid.h"
#include "io/mesh_io.h"
#include "mesh_service.h"
#include "store.h"
#include "voxel/voxel_io.h"
#include "ws_handler.h"

using namespace cgview;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const bench::Options opt = bench::parse_options(argc, argv, "slice_bench", false);
  const fs::path dir = fs::temp_directory_path() / ("cgview-slice-bench-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  server::Store store(dir / "data");
  server::MeshService meshes(store);
  server::Auth auth(store, false);
  std::printf("grid        slices  read+decode each (ms/slice)  kept decoded (ms/slice)  ratio\n");
  for (const int n : opt.quick ? std::vector<int>{128} : std::vector<int>{128, 256, 384}) {
    // A solid ball, as voxelize writes one: a bit grid in an NRRD file.
    VoxelGrid grid({n, n, n}, {0, 0, 0}, 1.0, VoxelType::bit);
    const double r = n * 0.45, c = n * 0.5;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i)
          if (std::hypot(i + 0.5 - c, j + 0.5 - c, k + 0.5 - c) < r) grid.set({i, j, k}, 1);
    const fs::path file = dir / ("grid" + std::to_string(n) + ".nrrd");
    std::ofstream(file, std::ios::binary) << encode_nrrd(grid);
    const server::JobArtifacts artifacts{
        [&](const std::string&, const std::string&, const std::string&, const server::Caller&) {
          return ExportedArtifact{read_file_bytes(file, std::uint64_t(1) << 40), "application/octet-stream",
                                  "grid.nrrd"};
        },
        [](const std::string&, const server::Caller&) {}};
    const int slices = 32;
    auto page = [&](std::size_t kept) {
      const server::WsHandler ws(meshes, artifacts, auth, nullptr, {std::size_t(4) << 20, 1 << 20, kept});
      server::WsConnection conn;
      conn.caller = server::Caller::local();
      return bench::best_seconds(opt.repeat,
                                 [&] {
                                   for (int s = 0; s < slices; ++s) {
                                     const auto replies = ws.handle(
                                         R"({"type":"get_slice","request_id":1,"job_id":"j","axis":"z","index":)" +
                                             std::to_string(s * n / slices) + "}",
                                         conn);
                                     if (replies.size() < 3) std::abort();
                                   }
                                 }) /
             slices;
    };
    const double each = page(0), kept = page(4);
    std::printf("%4d^3      %6d  %27.2f  %23.2f  %5.1fx\n", n, slices, each * 1e3, kept * 1e3, each / kept);
  }
  fs::remove_all(dir);
  return 0;
}
