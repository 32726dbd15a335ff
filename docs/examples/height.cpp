// height: each vertex's height along an axis, measured from the lowest vertex.
// Your own algorithm, in one file: "Build" compiles it on the server (its
// errors show at their lines), "Run" runs it on the mesh shown. Rename
// "height" in CGVIEW_REGISTER_FUNCTION below to name it.
#include <algorithm>
#include <string>
#include <vector>

#include "registry/registry.h"

namespace cgview {
namespace {  // names of this file alone: none meets one of CGView's

enum class HeightAxis { x, y, z };  // the choices of "axis", in order

struct HeightParams {
  HeightAxis axis = HeightAxis::z;  // the default, written once
  bool normalize = false;
  template <class V>
  void describe(V& v) {
    v.choice("axis", axis, {.label = "Axis", .help = "the up direction", .choices = {"x", "y", "z"}});
    v.boolean("normalize", normalize, {.label = "Normalize", .help = "divide by the mesh's height, giving 0..1"});
  }
};

struct HeightResult {
  ScalarField height{"height", Location::vertex, ColorHint::standard, {}};  // one value per vertex
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("height", height);
  }
};

HeightResult height(const Mesh& mesh, const HeightParams& p = {}, Context* context = nullptr) {
  check_params(p);  // the ranges and choices of describe, for a direct call
  const Context& ctx = context_or_none(context);
  if (mesh.num_vertices() == 0) throw InvalidInput("the mesh has no vertices");
  const int k = int(p.axis);  // x, y, z: 0, 1, 2
  double lo = mesh.positions[0][k], hi = lo;
  for (const Vec3& v : mesh.positions) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  HeightResult r;
  r.height.values.resize(mesh.num_vertices());
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (i % 65536 == 0) {
      ctx.check_cancelled();  // lets a job be cancelled
      ctx.progress(double(i) / double(mesh.num_vertices()), "heights");
    }
    const double h = mesh.positions[i][k] - lo;
    r.height.values[i] = float(p.normalize && hi > lo ? h / (hi - lo) : h);
  }
  ctx.progress(1.0, "done");
  return r;
}

CGVIEW_REGISTER_FUNCTION(height, height,
                         {.title = "Height along an axis",
                          .description = "Per-vertex height above the lowest vertex, along x, y or z.",
                          .area = "playground"})

}  // namespace
}  // namespace cgview
