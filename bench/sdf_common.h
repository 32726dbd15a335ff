// What the SDF benchmarks share (sdf_bench, sdf_gpu_bench): the sample
// meshes, the 1.42M-triangle one ("big": refined_elephant subdivided twice),
// and our whole sdf as the algorithm runs it.
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_util.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "registry/registry.h"
#include "sdf/sdf_rays.h"

namespace cgview::bench {

// Our whole sdf: rays with the face graph built beside them, post-processing
// (as the algorithm runs it).
inline std::vector<double> our_sdf(const Mesh& mesh, const sdf::SdfParams& p, bool smooth) {
  Context ctx;
  Adjacency graph;
  std::vector<double> v = sdf::raw_sdf(mesh, p, graph, &ctx, 0, 1).values;
  sdf::SdfParams q = p;
  q.smooth = smooth;
  sdf::postprocess(mesh, graph, v, q, ctx);
  return v;
}

inline Mesh sample_mesh(const std::string& name, const char* program) {
  const auto path = resolve_mesh_path(name);
  if (!path) {
    std::fprintf(stderr, "%s: no sample mesh %s (install libcgal-demo)\n", program, name.c_str());
    std::exit(1);
  }
  return read_mesh(*path);
}

struct SdfInput {
  std::string name;
  Mesh mesh;
};

// The four sample meshes and big, as --only and --quick (elephant alone) ask;
// any other sample mesh named in --only too (diplodocus, bunny00, ...).
inline std::vector<SdfInput> sdf_inputs(const Options& opt, const char* program) {
  const std::vector<std::string> usual{"elephant", "man", "armadillo", "refined_elephant"};
  std::vector<SdfInput> inputs;
  for (const std::string& n : usual)
    if (opt.wants(n) && (!opt.quick || n == "elephant")) inputs.push_back({n, sample_mesh(n, program)});
  for (const std::string& n : opt.only)
    if (n != "big" && std::find(usual.begin(), usual.end(), n) == usual.end())
      inputs.push_back({n, sample_mesh(n, program)});
  if (!opt.quick && opt.wants("big"))
    inputs.push_back({"big", subdivide_midpoint(subdivide_midpoint(sample_mesh("refined_elephant", program)))});
  return inputs;
}

}  // namespace cgview::bench
