// Chaotic encryption and steganography: throughput in vertices
// per second of chaos::encrypt, decrypt, embed and extract on a mesh of
// about 1M vertices (man.off, 17,495 vertices, midpoint-subdivided three
// times: 1.12M vertices), with
// writing the same mesh as binary PLY as a yardstick of what one pass over
// the mesh in memory costs.  Prints a Markdown table (docs/BENCHMARKS.md).
//
//   build/bin/chaos_bench [--repeat N] [--quick]     (--quick: man.off as it is)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>

#include "bench_util.h"
#include "chaos/embed.h"
#include "chaos/encrypt.h"
#include "io/mesh_io.h"
#include "io/samples.h"

using namespace cgview;

using bench::best_seconds;

int main(int argc, char** argv) {
  const bench::Options options = bench::parse_options(argc, argv, "chaos_bench", false);
  const int repeat = options.repeat;
  const bool quick = options.quick;
  const auto base = resolve_mesh_path("man.off");
  if (!base) {
    std::fprintf(stderr, "chaos_bench: sample meshes not found (install libcgal-demo, re-run cmake)\n");
    return 1;
  }
  Mesh mesh = read_mesh(*base);
  int times = 0;
  while (!quick && mesh.num_vertices() < 1000000) {
    mesh = subdivide_midpoint(mesh);
    ++times;
  }
  const std::string name = "man.off" + (times ? " subdivided " + std::to_string(times) + " times" : std::string());
  const double n = double(mesh.num_vertices());
  const std::string key = "correct horse battery staple";
  std::printf("mesh: %s, %zu vertices, %zu faces; best of %d runs\n\n", name.c_str(), mesh.num_vertices(),
              mesh.num_faces(), repeat);
  std::printf("| operation | settings | seconds | vertices/s |\n|---|---|---:|---:|\n");
  auto row = [&](const char* op, const std::string& settings, double s) {
    std::printf("| %s | %s | %.3f | %.3g |\n", op, settings.c_str(), s, n / s);
    std::fflush(stdout);
  };

  Mesh cipher, plain;
  row("encrypt", "vertices + faces", best_seconds(repeat, [&] { cipher = chaos::encrypt(mesh, key); }));
  row("decrypt", "vertices + faces", best_seconds(repeat, [&] { plain = chaos::decrypt(cipher, key); }));
  const Mesh expect = chaos::float32_copy(mesh);
  if (plain.positions != expect.positions || plain.faces != expect.faces) {
    std::fprintf(stderr, "chaos_bench: the round trip is not exact\n");
    return 1;
  }

  for (const auto& [label, bytes, k] :
       {std::tuple<std::string, std::size_t, int>{"1 KiB message, k = 4", 1024, 4},
        {"full capacity, k = 4", chaos::embed_capacity_bytes(mesh.num_vertices(), 4), 4}}) {
    std::string message(bytes, '\0');
    for (std::size_t i = 0; i < bytes; ++i) message[i] = char(i * 2654435761u >> 24);
    chaos::EmbedResult e;
    row("embed", label + " (" + std::to_string(bytes) + " B)",
        best_seconds(repeat, [&] { e = chaos::embed(mesh, key, message, k); }));
    chaos::ExtractResult x;
    row("extract", label, best_seconds(repeat, [&] { x = chaos::extract(e.mesh, key); }));
    if (x.message != message) {
      std::fprintf(stderr, "chaos_bench: the message did not come back\n");
      return 1;
    }
  }
  std::string ply;
  row("yardstick: write binary PLY", "write_mesh_bytes, in memory",
      best_seconds(repeat, [&] { ply = write_mesh_bytes(mesh, MeshFormat::ply); }));
  return 0;
}
