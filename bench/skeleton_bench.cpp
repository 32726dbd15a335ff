// Curve skeletons (issue 10), in one run: skeleton_projection (the paper's
// method, EGL: Mesa's llvmpipe on this machine unless a GPU is found)
// against CGAL's mean curvature flow skeletonization (skeleton_mcf), both
// through the registry with their defaults: time ratio and the metrics of
// skeleton_metrics side by side, and the distance between the two
// skeletons (fractions of the mesh's bounding box diagonal).
//
//   build/bin/skeleton_bench [--repeat N] [--quick] [--only elephant,...,big]
#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"
#include "skeleton/skeleton_metrics.h"

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
  Skeleton skeleton;
  Metrics metrics;
};

Run run(const std::string& algorithm, const Mesh& mesh, int repeat) {
  Run r;
  r.seconds = bench::best_seconds(repeat, [&] {
    Context ctx;
    AlgorithmResult res = find_algorithm(algorithm).run(mesh, {}, ctx);
    for (Artifact& a : res.artifacts) {
      if (auto* s = std::get_if<Skeleton>(&a.value)) r.skeleton = std::move(*s);
      if (auto* m = std::get_if<Metrics>(&a.value)) r.metrics = std::move(*m);
    }
  });
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  const bench::Options opt = bench::parse_options(argc, argv, "skeleton_bench");
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
    const Run proj = run("skeleton_projection", in.mesh, big ? 1 : opt.repeat);
    BBox box;
    for (const Vec3& p : in.mesh.positions) box.add(p);
    const SkeletonDistance d = skeleton_distance(mcf.skeleton, proj.skeleton);
    const auto row = [](const Metrics& m) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%5.0f %3.0f %4.0f %5.0f %5.3f", m.at("nodes"), m.at("branches"), m.at("endpoints"),
                    m.at("loops"), m.at("inside_fraction"));
      return std::string(buf);
    };
    std::printf("%-17s %8zu %9.3f %9.3f %6.1fx | %-28s | %-28s | %.3f / %.3f\n", in.name.c_str(), in.mesh.faces.size(),
                mcf.seconds, proj.seconds, mcf.seconds / proj.seconds, row(mcf.metrics).c_str(), row(proj.metrics).c_str(),
                d.hausdorff / box.diagonal(), d.mean / box.diagonal());
    std::printf("%-17s centredness mean: MCF %.3f, projection %.3f; projection stages: render %.3f s, votes %.3f s, thinning %.3f s\n",
                "", mcf.metrics.at("centredness_mean"), proj.metrics.at("centredness_mean"), proj.metrics.at("render_seconds"),
                proj.metrics.at("vote_seconds"), proj.metrics.at("thin_seconds"));
    std::fflush(stdout);
  }
  return 0;
}
