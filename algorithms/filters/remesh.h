// remesh: isotropic remeshing to a target edge length (Botsch and Kobbelt
// 2004), CGAL's PMP::isotropic_remeshing, one iteration per call.
//
//   Mesh m = read_mesh("bunny.off");
//   RemeshResult r = remesh(m, {.target_edge_length = 0.01, .iterations = 5});
//   write_mesh(r.mesh, "remeshed.off");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct RemeshParams {
  double target_edge_length = 0;
  int iterations = 3;
  bool repair = true;  // describe_repair (filters/repair_param.h)
  template <class V>
  void describe(V& v) {
    v.number("target_edge_length", target_edge_length,
             {.label = "Target edge length",
              .min = 0,
              .help = "the edge length to reach; 0 means the input's mean edge length"});
    v.integer("iterations", iterations,
              {.label = "Iterations", .min = 1, .max = 100, .help = "split/collapse/flip/relax rounds"});
    describe_repair(v, repair);
  }
};

struct RemeshResult {
  Mesh mesh;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a mesh without faces or whose edges all have zero
// length, or one that is not manifold with `repair` off.
RemeshResult remesh(const Mesh& mesh, const RemeshParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
