// Curve skeletons, in one run: skeleton_projection (the paper's
// method, EGL: Mesa's llvmpipe on this machine unless a GPU is found)
// against CGAL's mean curvature flow skeletonization (skeleton_mcf), both
// through the registry with their defaults: time ratio and the metrics of
// skeleton_metrics side by side, and the distance between the two
// skeletons (fractions of the mesh's bounding box diagonal).
//
//   build/bin/skeleton_bench [--repeat N] [--quick] [--only elephant,...,big]
//                            [--proj NAME=VALUE]...  (skeleton_projection's parameters)
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "bench_util.h"
#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"
#include "skeleton/skeleton_measures.h"
#include "voxel/voxel_ops.h"

using namespace cgview;

namespace {

Mesh sample(const std::string& name) {
  const auto path = resolve_mesh_path(name);
  if (!path) {
    std::fprintf(stderr, "skeleton_bench: no sample mesh %s (install libcgal-demo)\n", name.c_str());
    std::exit(1);
  }
  return read_mesh(*path);
}

struct Run {
  double seconds = 0;
  double cpu_seconds = 1e300;  // the process's CPU time (all threads), least over the runs
  Skeleton skeleton;
  Metrics metrics;
};

Run run(const std::string& algorithm, const Mesh& mesh, int repeat,
        const std::map<std::string, ParamValue>& params = {}) {
  Run r;
  r.seconds = bench::best_seconds(repeat, [&] {
    const double c0 = bench::cpu_seconds();
    Context ctx;
    AlgorithmResult res = find_algorithm(algorithm).run(mesh, params, ctx);
    for (Artifact& a : res.artifacts) {
      if (auto* s = std::get_if<Skeleton>(&a.value)) r.skeleton = std::move(*s);
      if (auto* m = std::get_if<Metrics>(&a.value)) r.metrics = std::move(*m);
    }
    r.cpu_seconds = std::min(r.cpu_seconds, bench::cpu_seconds() - c0);
  });
  return r;
}

std::string ends_by_pruning(const Skeleton& s, double diagonal) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%zu / %zu / %zu / %zu", endpoints_after_pruning(s, 0),
                endpoints_after_pruning(s, 0.02 * diagonal), endpoints_after_pruning(s, 0.05 * diagonal),
                endpoints_after_pruning(s, 0.10 * diagonal));
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  // --proj NAME=VALUE sets a parameter of skeleton_projection; the rest are
  // the common options.
  std::map<std::string, ParamValue> proj_params;
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--proj" && i + 1 < argc) {
      const std::string kv = argv[++i];
      const std::size_t eq = kv.find('=');
      const auto& specs = find_algorithm("skeleton_projection").params;
      const auto spec =
          std::find_if(specs.begin(), specs.end(), [&](const ParamSpec& s) { return s.name == kv.substr(0, eq); });
      if (eq == std::string::npos || spec == specs.end()) {
        std::fprintf(stderr, "skeleton_bench: --proj %s: not a parameter of skeleton_projection\n", kv.c_str());
        return 2;
      }
      proj_params[spec->name] = parse_param(*spec, kv.substr(eq + 1));
    } else {
      rest.push_back(argv[i]);
    }
  }
  const bench::Options opt = bench::parse_options(int(rest.size()), rest.data(), "skeleton_bench");
  struct Input {
    std::string name;
    Mesh mesh;
  };
  std::vector<Input> inputs;
  for (const char* n : {"elephant", "armadillo", "man", "refined_elephant"})
    if (opt.wants(n) && (!opt.quick || std::string(n) == "elephant")) inputs.push_back({n, sample(n)});
  if (!opt.quick && opt.wants("big")) {
    Mesh big = subdivide_midpoint(subdivide_midpoint(sample("refined_elephant")));
    inputs.push_back({"big", std::move(big)});
  }
  std::printf("%-17s %8s %9s %9s %7s | %-28s | %-28s | %s\n", "mesh", "faces", "MCF s", "proj s", "ratio",
              "MCF: nodes br ends loops in", "proj: nodes br ends loops in", "distance H / mean (x diag)");
  for (const Input& in : inputs) {
    const bool big = in.mesh.faces.size() > 500000;
    const Run mcf = run("skeleton_mcf", in.mesh, big ? 1 : opt.repeat);
    const Run proj = run("skeleton_projection", in.mesh, big ? 1 : opt.repeat, proj_params);
    const BBox box = bounding_box(in.mesh);
    const SkeletonDistance d = measure_distance(mcf.skeleton, proj.skeleton);
    const auto row = [](const Metrics& m) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%5.0f %3.0f %4.0f %5.0f %5.3f", m.at("nodes"), m.at("branches"),
                    m.at("endpoints"), m.at("loops"), m.at("inside_fraction"));
      return std::string(buf);
    };
    std::printf("%-17s %8zu %9.3f %9.3f %6.1fx | %-28s | %-28s | %.3f / %.3f\n", in.name.c_str(), in.mesh.faces.size(),
                mcf.seconds, proj.seconds, mcf.seconds / proj.seconds, row(mcf.metrics).c_str(),
                row(proj.metrics).c_str(), d.hausdorff / box.diagonal(), d.mean / box.diagonal());
    std::printf(
        "%-17s centredness mean: MCF %.3f, projection %.3f; projection stages, wall / CPU (last run): render %.3f / "
        "%.3f s, "
        "votes %.3f / %.3f s, thinning %.3f / %.3f s\n",
        "", mcf.metrics.at("centredness_mean"), proj.metrics.at("centredness_mean"), proj.metrics.at("render_seconds"),
        proj.metrics.at("render_cpu_seconds"), proj.metrics.at("vote_seconds"), proj.metrics.at("vote_cpu_seconds"),
        proj.metrics.at("thin_seconds"), proj.metrics.at("thin_cpu_seconds"));
    std::printf("%-17s CPU seconds (all threads; less disturbed by the load): MCF %.3f, projection %.3f, ratio %.1fx\n",
                "", mcf.cpu_seconds, proj.cpu_seconds, mcf.cpu_seconds / proj.cpu_seconds);
    std::printf(
        "%-17s ends once spurs shorter than 0 / 2%% / 5%% / 10%% of the diagonal are pruned (repeatedly): MCF %s, "
        "projection %s\n",
        "", ends_by_pruning(mcf.skeleton, box.diagonal()).c_str(),
        ends_by_pruning(proj.skeleton, box.diagonal()).c_str());
    // The limbs both have: at 5%, the ends within 10% of the diagonal of a
    // different end of the other's.
    {
      const std::vector<Vec3> ours = ends_after_pruning(proj.skeleton, 0.05 * box.diagonal());
      const std::vector<Vec3> theirs = ends_after_pruning(mcf.skeleton, 0.05 * box.diagonal());
      std::printf(
          "%-17s limbs: at 5%%, %zu of the projection's %zu ends are within 10%% of the diagonal of one of MCF's %zu\n",
          "", matched_ends(ours, theirs, 0.10 * box.diagonal()), ours.size(), theirs.size());
    }
    // Tunnels: the mesh's genus, and those of the vote grid (a run of its
    // own, keeping the votes), thresholded as the thinning's targets (0.25 x
    // the most votes) and as its domain (any vote).
    {
      const MeshReport report = mesh_report(in.mesh);
      Context ctx;
      AlgorithmResult res =
          find_algorithm("skeleton_projection").run(in.mesh, {{"intermediate", ParamValue(true)}}, ctx);
      for (const Artifact& a : res.artifacts)
        if (const auto* g = std::get_if<VoxelGrid>(&a.value); g && a.name == "votes") {
          const float top = value_range(*g).second;
          std::printf("%-17s tunnels: mesh genus %lld; vote grid: %zu at >= 0.25 x the most votes, %zu at any vote\n",
                      "", report.genus ? (long long)*report.genus : -1LL,
                      voxel_topology(threshold(*g, 0.25f * top - 1e-6f)).tunnels,
                      voxel_topology(threshold(*g, 0.f)).tunnels);
        }
    }
    std::fflush(stdout);
  }
  return 0;
}
