// Mesh loading: CGView's readers against CGAL's read_polygon_mesh, in one
// run, per format, on the largest sample mesh and on a 1M-triangle mesh made
// by subdividing a sample.  Prints a Markdown table with the ratio.
//
//   build/bin/io_bench [--repeat N] [--quick]
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <string>
#include <unistd.h>

#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "bench_util.h"
#include "io/samples.h"

namespace fs = std::filesystem;
using namespace cgview;

using bench::best_seconds;

namespace {

struct Case {
  const char* label;
  const char* ext;
  bool binary;
};

}  // namespace

int main(int argc, char** argv) {
  const bench::Options options = bench::parse_options(argc, argv, "io_bench");
  const int repeat = options.repeat;
  const bool quick = options.quick;
  const auto largest = resolve_mesh_path("refined_elephant.off");
  const auto base = resolve_mesh_path("bunny00.off");
  if (!largest || !base) {
    std::fprintf(stderr, "io_bench: sample meshes not found (install libcgal-demo, re-run cmake)\n");
    return 1;
  }
  struct Input {
    std::string name;
    Mesh mesh;
  };
  std::vector<Input> inputs;
  inputs.push_back({"refined_elephant (largest sample)", read_mesh(*largest)});
  if (!quick) inputs.push_back({"bunny00 subdivided twice", subdivide_midpoint(subdivide_midpoint(read_mesh(*base)))});

  const Case cases[] = {{"OFF", "off", false},       {"OBJ", "obj", false},       {"PLY binary", "ply", true},
                        {"PLY ascii", "ply", false}, {"STL binary", "stl", true}, {"STL ascii", "stl", false}};
  const fs::path dir = fs::temp_directory_path() / ("cgview-io-bench-" + std::to_string(::getpid()));
  fs::create_directories(dir);

  std::printf(
      "| mesh | triangles | format | file MB | CGView read s | CGView read + to Surface_mesh s | CGAL "
      "read_polygon_mesh s | CGAL / CGView |\n");
  std::printf("|---|---:|---|---:|---:|---:|---:|---:|\n");
  for (const Input& in : inputs) {
    for (const Case& c : cases) {
      if (!options.wants(c.label) && !options.wants(c.ext)) continue;
      const fs::path file = dir / (std::string("mesh_") + c.label[0] + c.label[4] + "." + c.ext);
      WriteOptions wo;
      wo.binary = c.binary;
      write_mesh(in.mesh, file, wo);
      std::size_t faces = 0, cgal_faces = 0;
      const double ours = best_seconds(repeat, [&] { faces = read_mesh(file).num_faces(); });
      const double ours_sm = best_seconds(repeat, [&] {
        auto sm = to_surface_mesh(read_mesh(file));
        faces = sm.mesh.number_of_faces();
      });
      const double cgal = best_seconds(repeat, [&] {
        SurfaceMesh sm;
        if (!CGAL::IO::read_polygon_mesh(file.string(), sm)) std::fprintf(stderr, "CGAL failed on %s\n", file.c_str());
        cgal_faces = sm.number_of_faces();
      });
      if (cgal_faces != faces)
        std::fprintf(stderr, "warning: %s: CGAL read %zu faces, CGView %zu\n", file.c_str(), cgal_faces, faces);
      std::printf("| %s | %zu | %s | %.1f | %.3f | %.3f | %.3f | %.1fx |\n", in.name.c_str(), in.mesh.num_faces(),
                  c.label, double(fs::file_size(file)) / 1e6, ours, ours_sm, cgal, cgal / ours);
      std::fflush(stdout);
      fs::remove(file);
    }
  }
  fs::remove_all(dir);
  return 0;
}
