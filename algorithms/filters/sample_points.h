// sample_points: points drawn uniformly at random over the surface's area,
// reproducible by seed.
//
//   Mesh m = read_mesh("bunny.off");
//   SamplePointsResult r = sample_points(m, {.count = 5000, .seed = 7});
//   write_mesh(r.points, "bunny_points.ply");  // a mesh with no faces
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct SamplePointsParams {
  int count = 10000;
  int seed = 0;
  template <class V>
  void describe(V& v) {
    v.integer("count", count, {.label = "Points", .min = 1, .max = 1e7, .help = "how many points to draw"});
    v.integer(
        "seed", seed,
        {.label = "Seed", .min = 0, .max = 2147483647, .help = "the random seed: the same seed, the same points"});
  }
};

struct SamplePointsResult {
  Mesh points;  // a point cloud: positions only, no faces
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("points", points);
  }
};

// Throws InvalidInput for a mesh without faces or without area.
SamplePointsResult sample_points(const Mesh& mesh, const SamplePointsParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
