// The SDF's rays in an OpenGL compute shader (rays/gpu_ray_caster.h) against
// the same rays on Embree and against CGAL's sdf_values, in one run, with
// CGAL's options (25 rays, 120 degrees, uniform weights, MAD outliers):
// - the BVH: the GPU caster's build and upload against Embree's build;
// - the rays (raw_sdf): rays per second on Embree (every core) and in the
//   shader, and their ratio;
// - the whole sdf (rays and post-processing, none on the 1.42M-triangle
//   mesh, as sdf_bench): CGAL, ours on Embree, ours on the GPU, the ratios,
//   and Pearson r between our two paths' values.
// On Mesa's llvmpipe (no GPU) the shader runs on the CPU, far slower than
// Embree: the numbers that matter come from a machine with a GPU
// (bench/gpu_sdf.sh).  CGAL's time can be given instead of measured
// (--cgal-seconds big=461): CGAL runs on one CPU core, for minutes on big,
// and a GPU machine's time is short; the row says so.
//
//   build/bin/sdf_gpu_bench [--repeat N] [--quick] [--only elephant,...] [--cgal-seconds NAME=S,...]
#include <CGAL/mesh_segmentation.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/surface_mesh.h"
#include "rays/gpu_ray_caster.h"
#include "rays/ray_caster.h"
#include "sdf_common.h"

using namespace cgview;

namespace {

// --cgal-seconds NAME=S,...: taken out of argv before the common options.
std::map<std::string, double> given_cgal_seconds(int& argc, char** argv) {
  std::map<std::string, double> out;
  for (const std::string& item :
       bench::comma_list(bench::take_option(argc, argv, "--cgal-seconds", true).value_or(""))) {
    const std::size_t eq = item.find('=');
    if (eq == std::string::npos) {
      std::fprintf(stderr, "sdf_gpu_bench: --cgal-seconds wants NAME=SECONDS, got '%s'\n", item.c_str());
      std::exit(2);
    }
    out[item.substr(0, eq)] = std::atof(item.c_str() + eq + 1);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const std::map<std::string, double> given = given_cgal_seconds(argc, argv);
  const bench::Options opt = bench::parse_options(argc, argv, "sdf_gpu_bench");
  const std::vector<bench::SdfInput> inputs = bench::sdf_inputs(opt, "sdf_gpu_bench");
  sdf::SdfParams cpu{.weights = sdf::Weights::uniform, .outliers = sdf::Outliers::mad};
  cpu.device = sdf::RayDevice::cpu;
  sdf::SdfParams gpu = cpu;
  gpu.device = sdf::RayDevice::gpu;
  if (inputs.empty()) return 0;
  {
    const GpuRayCaster probe(inputs.front().mesh);
    std::printf("GPU rays on: %s (%s, %s); automatic choice here: %s\n", probe.info().gl_renderer.c_str(),
                probe.info().gl_version.c_str(), probe.info().platform.c_str(),
                sdf::ray_device({}) == sdf::RayDevice::gpu ? "GPU" : "Embree");
  }
  std::printf("\nBVH: the GPU caster's build + upload against Embree's build (s)\n");
  std::printf("%-18s %9s %10s %10s %9s\n", "mesh", "faces", "Embree s", "GPU s", "nodes");
  for (const bench::SdfInput& in : inputs) {
    std::size_t nodes = 0;
    const double embree_s = bench::best_seconds(opt.repeat, [&] { const RayCaster c(in.mesh); });
    const double gpu_s = bench::best_seconds(opt.repeat, [&] { nodes = GpuRayCaster(in.mesh).bvh_nodes(); });
    std::printf("%-18s %9zu %10.3f %10.3f %9zu\n", in.name.c_str(), in.mesh.faces.size(), embree_s, gpu_s, nodes);
    std::fflush(stdout);
  }

  std::printf(
      "\nthe SDF's rays (raw_sdf, 25 per face): Embree on every core against the compute shader;\n"
      "GPU s: the whole raw_sdf, of which set-up (the GPU caster's, as above) and in shader (the\n"
      "calling thread's wait on the shader's chunks, the cores meanwhile taking hits)\n");
  std::printf("%-18s %10s %12s %12s %8s %9s %9s\n", "mesh", "rays", "Embree r/s", "GPU r/s", "GPU/Emb", "GPU s",
              "in shader");
  for (const bench::SdfInput& in : inputs) {
    std::size_t rays = 0;
    double in_shader = HUGE_VAL;
    const double embree_s = bench::best_seconds(opt.repeat, [&] { rays = sdf::raw_sdf(in.mesh, cpu).rays_cast; });
    const double gpu_s = bench::best_seconds(
        opt.repeat, [&] { in_shader = std::min(in_shader, sdf::raw_sdf(in.mesh, gpu).gpu_seconds); });
    std::printf("%-18s %10zu %12.3g %12.3g %7.2fx %9.3f %9.3f\n", in.name.c_str(), rays, double(rays) / embree_s,
                double(rays) / gpu_s, embree_s / gpu_s, gpu_s, in_shader);
    std::fflush(stdout);
  }

  std::printf("\nthe whole sdf against CGAL 5.5 sdf_values (* CGAL's time given, not measured in this run)\n");
  std::printf("%-18s %9s %10s %10s %10s %9s %9s %9s\n", "mesh", "faces", "CGAL s", "Embree s", "GPU s", "CGAL/GPU",
              "Emb/GPU", "Pearson");
  for (const bench::SdfInput& in : inputs) {
    const bool big = in.mesh.faces.size() > 500000;
    double cgal_s = 0;
    const auto it = given.find(in.name);
    if (it != given.end()) {
      cgal_s = it->second;
    } else {
      SurfaceMesh sm = manifold_surface_mesh(in.mesh, "sdf_gpu_bench");
      auto map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
      cgal_s = bench::best_seconds(big ? 1 : opt.repeat,
                                   [&] { CGAL::sdf_values(sm, map, 2.0 * std::numbers::pi / 3.0, 25, !big); });
    }
    std::vector<double> on_cpu, on_gpu;
    const double cpu_s = bench::best_seconds(opt.repeat, [&] { on_cpu = bench::our_sdf(in.mesh, cpu, !big); });
    const double gpu_s = bench::best_seconds(opt.repeat, [&] { on_gpu = bench::our_sdf(in.mesh, gpu, !big); });
    std::printf("%-18s %9zu %9.3f%s %10.3f %10.3f %8.1fx %8.2fx %9.6f%s\n", in.name.c_str(), in.mesh.faces.size(),
                cgal_s, it != given.end() ? "*" : " ", cpu_s, gpu_s, cgal_s / gpu_s, cpu_s / gpu_s,
                sdf::pearson(on_cpu, on_gpu), big ? "  (without post-processing)" : "");
    std::fflush(stdout);
  }
  return 0;
}
