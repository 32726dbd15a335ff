// height: each vertex's height along an axis, measured from the lowest vertex.
// Your own algorithm, in one file: "Build" compiles it on the server (its
// errors show at their lines), "Run" runs it on the mesh shown. Rename
// "height" in CGVIEW_REGISTER_ALGORITHM below to name it.
#include <algorithm>
#include <string>

#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  std::string axis = "z";  // the default, written once
  bool normalize = false;
  template <class V>
  void describe(V& v) {
    v.choice("axis", axis, {.label = "Axis", .help = "the up direction", .choices = {"x", "y", "z"}});
    v.boolean("normalize", normalize, {.label = "Normalize", .help = "divide by the mesh's height, giving 0..1"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_vertices() == 0) throw InvalidInput("the mesh has no vertices");
  const int k = p.axis == "x" ? 0 : p.axis == "y" ? 1 : 2;
  double lo = mesh.positions[0][k], hi = lo;
  for (const Vec3& v : mesh.positions) lo = std::min(lo, v[k]), hi = std::max(hi, v[k]);
  ScalarField field{"height", Location::vertex, ColorHint::standard, {}};
  field.values.resize(mesh.num_vertices());
  for (std::size_t i = 0; i < mesh.num_vertices(); ++i) {
    if (i % 65536 == 0) {
      ctx.check_cancelled();  // lets a job be cancelled
      ctx.progress(double(i) / double(mesh.num_vertices()), "heights");
    }
    const double h = mesh.positions[i][k] - lo;
    field.values[i] = float(p.normalize && hi > lo ? h / (hi - lo) : h);
  }
  ctx.progress(1.0, "done");
  return {{{"height", field}}, {}};
}

CGVIEW_REGISTER_ALGORITHM(height, Params, run,
                          {.title = "Height along an axis",
                           .description = "Per-vertex height above the lowest vertex, along x, y or z.",
                           .area = "playground",
                           .outputs = {{"height", OutputKind::scalar_field}}})

}  // namespace
}  // namespace cgview
