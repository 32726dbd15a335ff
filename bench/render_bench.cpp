// Rendering for algorithms: orthographic silhouettes and depth buffers of a
// mesh from N viewpoints on a Fibonacci sphere, with the EGL renderer
// (Renderer::capture, one upload then N draws and read-backs), against a CPU
// ray cast of the same pixels with CGAL's AABB tree (first_intersection per
// pixel centre, along the same camera rays), on every core for both
// (llvmpipe's threads; std::thread over the views for CGAL).  Meshes:
// refined_elephant and a 1.2M-triangle mesh (bunny00 subdivided twice).
// Prints a Markdown table with the ratio and how far the two answers agree.
//
//   build/bin/render_bench [--views N] [--quick] [--large-only]
//
// With --small-views: what skeleton_projection asks of the renderer, 48
// orthographic 256x256 depth views (24 directions, each d and -d) through
// capture_cameras with 1 and 2 contexts, on elephant, armadillo and (with
// --large) refined_elephant subdivided twice; the median of --repeat runs
// (default 7), wall clock and CPU-seconds; fails if a run's views differ
// from the first run's by one bit.  --only: that sample mesh alone.
//
//   build/bin/render_bench --small-views [--repeat N] [--large] [--only elephant.off]
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "render/views.h"

using namespace cgview;
using namespace cgview::render;

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct CpuView {
  std::vector<std::uint8_t> silhouette;
  std::vector<float> depth;  // window depth, as the renderer gives it
};

// The CPU reference: one ray per pixel centre, first hit, its window depth.
std::vector<CpuView> cpu_cast(const Tree& tree, const std::vector<CameraMatrices>& cams) {
  std::vector<CpuView> out(cams.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    for (std::size_t v; (v = next++) < cams.size();) {
      const CameraMatrices& c = cams[v];
      // CameraMatrices::ray() inverts the matrices per call: invert once per view.
      const Mat4 vp = c.view_projection(), inv = inverse(vp);
      const Vec3 dir = normalized(transform_point(inv, {0, 0, 1}) - transform_point(inv, {0, 0, -1}));
      CpuView& o = out[v];
      o.silhouette.assign(std::size_t(c.width) * c.height, 0);
      o.depth.assign(o.silhouette.size(), 1.0f);
      for (int y = 0; y < c.height; ++y)
        for (int x = 0; x < c.width; ++x) {
          const Ray r{transform_point(inv, {2 * (x + 0.5) / c.width - 1, 1 - 2 * (y + 0.5) / c.height, -1}), dir};
          const K::Ray_3 ray(K::Point_3(r.origin.x, r.origin.y, r.origin.z),
                             K::Vector_3(r.direction.x, r.direction.y, r.direction.z));
          const auto hit = tree.first_intersection(ray);
          if (!hit) continue;
          const K::Point_3* p = boost::get<K::Point_3>(&hit->first);
          if (!p) continue;
          const std::size_t i = std::size_t(y) * c.width + x;
          o.silhouette[i] = 1;
          o.depth[i] = float(0.5 * (transform_point(vp, Vec3{p->x(), p->y(), p->z()}).z + 1));
        }
    }
  };
  std::vector<std::thread> threads;
  const unsigned n = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned t = 0; t < n; ++t) threads.emplace_back(work);
  for (auto& t : threads) t.join();
  return out;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

int small_views(int repeat, bool large, const std::string& only) {
  struct Input {
    std::string name;
    Mesh mesh;
  };
  std::vector<Input> inputs;
  std::vector<std::string> names = {"elephant.off", "armadillo.off"};
  if (!only.empty()) names = {only};
  for (const std::string& name : names) {
    const auto path = resolve_mesh_path(name);
    if (!path) {
      std::fprintf(stderr, "render_bench: the sample mesh %s is missing (build/samples)\n", name.c_str());
      return 1;
    }
    inputs.push_back({name, read_mesh(*path)});
  }
  if (large && only.empty()) {
    const auto path = resolve_mesh_path("refined_elephant.off");
    if (!path) return 1;
    inputs.push_back({"refined_elephant subdivided twice", subdivide_midpoint(subdivide_midpoint(read_mesh(*path)))});
  }
  Renderer renderer;
  std::printf("renderer: %s (%s platform); 48 views of 256x256, depth only; median of %d runs\n\n",
              renderer.info().gl_renderer.c_str(), renderer.info().platform.c_str(), repeat);
  std::printf(
      "| mesh | faces | 1 context: wall | CPU-s | 2 contexts: wall | CPU-s | new Renderer + 2 contexts: wall | "
      "24 pairs with back depth, 2 contexts: wall | CPU-s |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const Input& in : inputs) {
    const BBox box = bounding_box(in.mesh);
    // The 48 views as 24 antipodal pairs, as skeleton_projection takes them:
    // drawn one by one, or one drawing a pair with back depth.
    std::vector<CameraMatrices> cams, pairs;
    for (const Vec3& d : sphere_directions(24)) {
      cams.push_back(orthographic_view(d, box, 256, 256));
      cams.push_back(orthographic_view(d * -1.0, box, 256, 256));
      pairs.push_back(cams[cams.size() - 2]);
    }
    const std::vector<ViewCapture> reference = capture_cameras(renderer, in.mesh, cams, 1);  // warm-up
    // A hash of every depth bit, to compare builds of the renderer.
    std::uint64_t hash = 1469598103934665603ull;
    for (const ViewCapture& v : reference)
      for (float d : v.depth) {
        std::uint32_t bits;
        std::memcpy(&bits, &d, 4);
        hash = (hash ^ bits) * 1099511628211ull;
      }
    std::fprintf(stderr, "%s: depth hash %016llx\n", in.name.c_str(), (unsigned long long)hash);
    std::vector<double> wall[4], cpu[3];
    for (int r = 0; r < repeat; ++r) {
      // Alternated, so that the load of a shared machine falls on all three alike.
      for (int contexts : {1, 2}) {
        const auto t0 = std::chrono::steady_clock::now();
        const double c0 = bench::cpu_seconds();
        const std::vector<ViewCapture> v = capture_cameras(renderer, in.mesh, cams, contexts);
        wall[contexts - 1].push_back(seconds_since(t0));
        cpu[contexts - 1].push_back(bench::cpu_seconds() - c0);
        for (std::size_t k = 0; k < v.size(); ++k)
          if (v[k].depth != reference[k].depth || v[k].silhouette != reference[k].silhouette) {
            std::fprintf(stderr, "render_bench: view %zu of %d contexts differs from the first run's\n", k, contexts);
            return 1;
          }
      }
      const auto t0 = std::chrono::steady_clock::now();
      Renderer fresh;
      capture_cameras(fresh, in.mesh, cams, 2);
      wall[2].push_back(seconds_since(t0));
      const auto t1 = std::chrono::steady_clock::now();
      const double c1 = bench::cpu_seconds();
      const std::vector<ViewCapture> both = capture_cameras(renderer, in.mesh, pairs, 2, {.back_depth = true});
      wall[3].push_back(seconds_since(t1));
      cpu[2].push_back(bench::cpu_seconds() - c1);
      for (std::size_t k = 0; k < both.size(); ++k)
        if (both[k].depth != reference[2 * k].depth) {
          std::fprintf(stderr, "render_bench: pair %zu's front depth differs from its view's\n", k);
          return 1;
        }
    }
    std::printf("| %s | %zu | %.1f ms | %.3f | %.1f ms | %.3f | %.1f ms | %.1f ms | %.3f |\n", in.name.c_str(),
                in.mesh.faces.size(), median(wall[0]) * 1e3, median(cpu[0]), median(wall[1]) * 1e3, median(cpu[1]),
                median(wall[2]) * 1e3, median(wall[3]) * 1e3, median(cpu[2]));
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool quick = false, large_only = false, small = false, large = false;
  std::string only;
  int views = 100, repeat = 7;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--small-views")) small = true;
    else if (!std::strcmp(argv[i], "--large")) large = true;
    else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) only = argv[++i];
    else if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--views") && i + 1 < argc) views = std::atoi(argv[++i]);
    else if (!std::strcmp(argv[i], "--large-only")) large_only = true;
    else {
      std::fprintf(stderr,
                   "usage: render_bench [--views N] [--quick] [--large-only] | --small-views [--repeat N] [--large] "
                   "[--only MESH.off]\n");
      return 2;
    }
  }
  if (small) return small_views(repeat, large, only);
  if (quick) views = std::min(views, 10);
  set_render_log([](const std::string& m) { std::fprintf(stderr, "%s\n", m.c_str()); });
  Renderer renderer;
  std::printf("renderer: %s (%s, %s platform%s); %u cores; %d views per run\n\n", renderer.info().gl_renderer.c_str(),
              renderer.info().gl_version.c_str(), renderer.info().platform.c_str(),
              renderer.info().software ? ", software" : ", GPU", std::thread::hardware_concurrency(), views);

  struct Input {
    std::string name;
    Mesh mesh;
  };
  std::vector<Input> inputs;
  const auto elephant = resolve_mesh_path("refined_elephant.off");
  const auto bunny = resolve_mesh_path("bunny00.off");
  if (!elephant || !bunny) {
    std::fprintf(stderr, "render_bench: the sample meshes are missing (build/samples)\n");
    return 1;
  }
  if (!large_only) inputs.push_back({"refined_elephant", read_mesh(*elephant)});
  if (!quick || large_only)
    inputs.push_back({"bunny00 subdivided twice", subdivide_midpoint(subdivide_midpoint(read_mesh(*bunny)))});

  const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
  std::printf(
      "| mesh | faces | size | views | EGL first call (upload + 1 view) | EGL views | per view | EGL views, %d "
      "contexts | per view | AABB tree build | CPU ray cast | per view | ratio CPU/EGL (1 context) | ratio CPU/EGL (%d "
      "contexts) | CPU-seconds EGL / EGL %d / ray cast | silhouettes agree | depth error (pixels) |\n",
      cores, cores, cores);
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Input& in : inputs) {
    Triangles tris;
    tris.reserve(in.mesh.faces.size());
    for (const Tri& t : in.mesh.faces) {
      const Vec3 &a = in.mesh.positions[t[0]], &b = in.mesh.positions[t[1]], &c = in.mesh.positions[t[2]];
      tris.emplace_back(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z), K::Point_3(c.x, c.y, c.z));
    }
    auto t0 = std::chrono::steady_clock::now();
    Tree tree(tris.begin(), tris.end());
    tree.build();
    const double build_s = seconds_since(t0);
    for (int size : quick ? std::vector<int>{256} : std::vector<int>{256, 512}) {
      const std::vector<Vec3> dirs = sphere_directions(views);
      const BBox box = bounding_box(in.mesh);
      std::vector<CameraMatrices> cams;
      for (const Vec3& d : dirs) cams.push_back(orthographic_view(d, box, size, size));
      // Upload alone: one view.
      t0 = std::chrono::steady_clock::now();
      renderer.capture(in.mesh, {cams[0]});
      const double one_s = seconds_since(t0);
      t0 = std::chrono::steady_clock::now();
      double c0 = bench::cpu_seconds();
      const std::vector<ViewCapture> gpu = renderer.capture(in.mesh, cams);
      const double gpu_s = seconds_since(t0), gpu_cpu = bench::cpu_seconds() - c0;
      // The same views split over one context per core.
      const int contexts = cores;
      ViewsParams vp;
      vp.views = views;
      vp.width = vp.height = size;
      vp.contexts = contexts;
      t0 = std::chrono::steady_clock::now();
      c0 = bench::cpu_seconds();
      const std::vector<ViewCapture> gpu_n = capture_views(renderer, in.mesh, vp);
      const double gpu_n_s = seconds_since(t0), gpu_n_cpu = bench::cpu_seconds() - c0;
      if (gpu_n.size() != gpu.size() || gpu_n.back().depth != gpu.back().depth)
        std::fprintf(stderr, "render_bench: the views of %d contexts differ from those of one\n", contexts);
      t0 = std::chrono::steady_clock::now();
      c0 = bench::cpu_seconds();
      const std::vector<CpuView> cpu = cpu_cast(tree, cams);
      const double cpu_s = seconds_since(t0), cpu_cpu = bench::cpu_seconds() - c0;
      // Agreement: silhouette pixels equal; depth difference in pixel sizes where both hit.
      std::size_t same = 0, total = 0, both = 0;
      double depth_err = 0;
      for (std::size_t v = 0; v < gpu.size(); ++v) {
        const double range = 2.1 * 0.5 * box.diagonal();  // far - near of orthographic_view, in world units
        const double pixel = cams[v].pixel_size_at(0);
        for (std::size_t i = 0; i < gpu[v].silhouette.size(); ++i) {
          ++total;
          same += gpu[v].silhouette[i] == cpu[v].silhouette[i];
          if (gpu[v].silhouette[i] && cpu[v].silhouette[i]) {
            ++both;
            depth_err += std::abs(double(gpu[v].depth[i]) - cpu[v].depth[i]) * range / pixel;
          }
        }
      }
      std::printf(
          "| %s | %zu | %d² | %d | %.0f ms | %.3f s | %.1f ms | %.3f s | %.1f ms | %.2f s | %.2f s | %.1f ms | %.1f | "
          "%.1f | %.1f / %.1f / %.1f | %.3f%% | %.3f mean |\n",
          in.name.c_str(), in.mesh.faces.size(), size, views, one_s * 1e3, gpu_s, gpu_s / views * 1e3, gpu_n_s,
          gpu_n_s / views * 1e3, build_s, cpu_s, cpu_s / views * 1e3, cpu_s / gpu_s, cpu_s / gpu_n_s, gpu_cpu,
          gpu_n_cpu, cpu_cpu, 100.0 * same / total, both ? depth_err / both : 0.0);
      std::fflush(stdout);
    }
  }
  std::printf(
      "\nEGL views: upload once, then per view a draw and the read-back of depth (silhouette = depth < 1);\n"
      "CPU: CGAL AABB_tree::first_intersection per pixel centre on %u threads, tree build not included.\n"
      "Times are wall clock; CPU-seconds (getrusage, all threads) are steadier on a shared machine.\n",
      std::thread::hardware_concurrency());
  return 0;
}
