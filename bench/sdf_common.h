// What the SDF benchmarks share (sdf_bench, sdf_gpu_bench): the sample
// meshes, the 1.42M-triangle one ("big": refined_elephant subdivided twice),
// and our whole sdf as the algorithm runs it.
#pragma once

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

// Our whole sdf: face graph, rays, post-processing (as the algorithm runs it).
inline std::vector<double> our_sdf(const Mesh& mesh, const sdf::SdfParams& p, bool smooth) {
  Context ctx;
  const Adjacency graph = face_neighbors(mesh, edge_topology(mesh));
  std::vector<double> v = sdf::raw_sdf(mesh, p).values;
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

// The four sample meshes and big, as --only and --quick (elephant alone) ask.
inline std::vector<SdfInput> sdf_inputs(const Options& opt, const char* program) {
  std::vector<SdfInput> inputs;
  for (const char* n : {"elephant", "man", "armadillo", "refined_elephant"})
    if (opt.wants(n) && (!opt.quick || std::string(n) == "elephant")) inputs.push_back({n, sample_mesh(n, program)});
  if (!opt.quick && opt.wants("big"))
    inputs.push_back({"big", subdivide_midpoint(subdivide_midpoint(sample_mesh("refined_elephant", program)))});
  return inputs;
}

}  // namespace cgview::bench
