// The SDF's bilateral filter (CGAL's Postprocess_sdf_values rule), in one
// run on the same raw values:
// - CGAL 5.5's Bilateral_filtering (a std::map of the window per face), on
//   the sample meshes only: on the 1.42M-triangle mesh it takes hours;
// - the filter as it was: a breadth-first walk per face in the file's face
//   order, two exp per neighbour (kept here as the reference for that mesh);
// - ours, exact (sdf::bilateral_smooth);
// - ours, sampled (sdf::bilateral_smooth_sampled, what the sdf takes where
//   the window and the mesh are large, sdf/bilateral_filter.h);
// times, the speed-ups, and the largest and mean difference of our exact
// values from theirs (CGAL's; the filter as it was where CGAL does not run)
// and of the sampled values from our exact ones, as fractions of the
// smoothed values' range.  Then the whole sdf (rays and post-processing) on
// each mesh.
//
//   build/bin/sdf_smooth_bench [--repeat N] [--quick] [--only elephant,...,big,diplodocus,...]
#include <CGAL/Surface_mesh_segmentation/internal/Filters.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "sdf_common.h"
#include "core/threads.h"
#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "sdf/bilateral_sampled.h"
#include "sdf/sdf.h"
#include "sdf/sdf_rays.h"

using namespace cgview;

namespace {

// The filter as it was: one walk per face, the window's faces in a list with
// their rings, two exp per neighbour, faces in the file's order, blocks of
// 1024 faces shared by every core.
void filter_as_it_was(const Adjacency& graph, std::vector<double>& values, int window) {
  const std::size_t n = values.size();
  const double spatial = window / 2.0;
  std::vector<double> out = values;
  std::atomic<std::size_t> next{0};
  on_threads(int(std::max(1u, std::thread::hardware_concurrency())), [&](int) {
    std::vector<std::uint32_t> stamp(n, 0);
    std::uint32_t epoch = 0;
    std::vector<std::pair<std::uint32_t, int>> ring;
    for (std::size_t b; (b = next.fetch_add(1024)) < n;)
      for (std::size_t f = b; f < std::min(n, b + 1024); ++f) {
        ++epoch;
        ring.assign(1, {std::uint32_t(f), 0});
        stamp[f] = epoch;
        for (std::size_t k = 0; k < ring.size(); ++k) {
          const auto [g, level] = ring[k];
          if (level >= window) continue;
          for (const std::uint32_t* h = graph.begin(g); h != graph.end(g); ++h)
            if (stamp[*h] != epoch) stamp[*h] = epoch, ring.push_back({*h, level + 1});
        }
        const double c = values[f];
        double dev = 0;
        for (auto& [g, level] : ring) dev += (values[g] - c) * (values[g] - c);
        dev = std::sqrt(dev / double(ring.size()));
        if (dev == 0) continue;
        const double range = 1.5 * dev;
        double sum = 0, wsum = 0;
        for (auto& [g, level] : ring) {
          const double dv = values[g] - c;
          const double w =
              std::exp(-0.5 * (level / spatial) * (level / spatial)) * std::exp(-0.5 * (dv / range) * (dv / range));
          sum += values[g] * w;
          wsum += w;
        }
        out[f] = sum / wsum;
      }
  });
  values = std::move(out);
}

void cgal_filter(const Mesh& mesh, std::vector<double>& values, int window) {
  SurfaceMesh sm = manifold_surface_mesh(mesh, "sdf_smooth_bench");
  auto map = sm.add_property_map<SurfaceMesh::Face_index, double>("f:sdf", 0.0).first;
  for (SurfaceMesh::Face_index f : sm.faces()) map[f] = values[f.idx()];
  CGAL::internal::Bilateral_filtering<SurfaceMesh>()(sm, std::size_t(window), map);
  for (SurfaceMesh::Face_index f : sm.faces()) values[f.idx()] = map[f];
}

struct Difference {
  double largest = 0, mean = 0;  // of the reference's range
};
Difference difference(const std::vector<double>& ours, const std::vector<double>& reference) {
  const auto [lo, hi] = std::minmax_element(reference.begin(), reference.end());
  const double range = *hi > *lo ? *hi - *lo : 1.0;
  Difference d;
  for (std::size_t i = 0; i < ours.size(); ++i) {
    const double e = std::abs(ours[i] - reference[i]) / range;
    d.largest = std::max(d.largest, e);
    d.mean += e;
  }
  d.mean /= double(std::max<std::size_t>(ours.size(), 1));
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  const bench::Options opt = bench::parse_options(argc, argv, "sdf_smooth_bench");
  const std::vector<bench::SdfInput> inputs = bench::sdf_inputs(opt, "sdf_smooth_bench");

  std::printf("bilateral filter of the raw SDF (default window), against CGAL 5.5 and the filter as it was\n");
  std::printf("%-17s %8s %6s %9s %9s %9s %8s %8s %8s %11s %11s | %9s %8s %8s %10s %10s\n", "mesh", "faces", "window",
              "CGAL s", "was s", "ours s", "x CGAL", "x was", "x cpu", "max diff", "mean diff", "sampled s", "x was",
              "own w %", "max vs ours", "mean");
  for (const auto& [name, mesh] : inputs) {
    const bool big = mesh.faces.size() > 500000;
    const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
    std::vector<double> raw = sdf::raw_sdf(mesh, {}).values;
    sdf::fill_missing(mesh, graph, raw);
    const int window = sdf::default_window(raw.size());
    std::vector<double> cgal, was, ours, sampled;
    const double cgal_s = big ? 0
                              : bench::best_seconds(
                                    opt.repeat, [&] { cgal = raw; }, [&] { cgal_filter(mesh, cgal, window); });
    // CPU seconds too: steadier than the wall clock when others share the cores.
    double cpu = bench::cpu_seconds();
    const double was_s = bench::best_seconds(
        opt.repeat, [&] { was = raw; }, [&] { filter_as_it_was(graph, was, window); });
    const double was_cpu = (bench::cpu_seconds() - cpu) / opt.repeat;
    cpu = bench::cpu_seconds();
    const double ours_s = bench::best_seconds(
        opt.repeat, [&] { ours = raw; }, [&] { sdf::bilateral_smooth(graph, ours, window); });
    const double ours_cpu = (bench::cpu_seconds() - cpu) / opt.repeat;
    sdf::SampledFilterStats stats;
    const double sampled_s = bench::best_seconds(
        opt.repeat, [&] { sampled = raw; },
        [&] { sdf::bilateral_smooth_sampled(mesh, graph, sampled, window, nullptr, {}, &stats); });
    const Difference d = difference(ours, big ? was : cgal), ds = difference(sampled, ours);
    char cgal_col[16] = "-", ratio_col[16] = "-";
    if (!big) {
      std::snprintf(cgal_col, sizeof cgal_col, "%.3f", cgal_s);
      std::snprintf(ratio_col, sizeof ratio_col, "%.1fx", cgal_s / ours_s);
    }
    std::printf(
        "%-17s %8zu %6d %9s %9.3f %9.3f %8s %7.1fx %7.1fx %10.2g%% %10.2g%% | %9.3f %7.1fx %7.1f%% %10.3f%% "
        "%9.4f%%%s\n",
        name.c_str(), mesh.faces.size(), window, cgal_col, was_s, ours_s, ratio_col, was_s / ours_s, was_cpu / ours_cpu,
        100 * d.largest, 100 * d.mean, sampled_s, was_s / sampled_s,
        100.0 * double(stats.exact) / double(mesh.faces.size()), 100 * ds.largest, 100 * ds.mean,
        big ? "  (exact: differences from the filter as it was)" : "  (exact: differences from CGAL's)");
    std::fflush(stdout);
  }

  std::printf("\nthe whole sdf with its defaults (rays, holes filled, bilateral filter, normalization)\n");
  std::printf("%-17s %8s %9s\n", "mesh", "faces", "sdf s");
  for (const auto& [name, mesh] : inputs) {
    const double s = bench::best_seconds(opt.repeat, [&] { (void)sdf::sdf(mesh); });
    std::printf("%-17s %8zu %9.3f\n", name.c_str(), mesh.faces.size(), s);
    std::fflush(stdout);
  }
  return 0;
}
