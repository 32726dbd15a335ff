// A whole algorithm in one file, compiled only into registry_test: the proof
// that CGVIEW_REGISTER_ALGORITHM is all a new algorithm needs (no list to
// edit, no header).  registry_test.cpp finds it through algorithms() alone.
#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  std::string axis = "z";
  int scale = 2;
  template <class V>
  void describe(V& v) {
    v.choice("axis", axis, {.label = "Axis", .help = "the coordinate to read", .choices = {"x", "y", "z"}});
    v.integer("scale", scale, {.label = "Scale", .min = 1, .max = 10, .help = "multiply the coordinate by this"});
  }
};

// One value per vertex: scale times the chosen coordinate; and the count.
AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  const int k = p.axis == "x" ? 0 : p.axis == "y" ? 1 : 2;
  ScalarField field{"test_coordinate", Location::vertex, ColorHint::standard, {}};
  for (const Vec3& v : mesh.positions) field.values.push_back(float(p.scale * v[k]));
  ctx.progress(1.0, "done");
  return {{{"coordinate", field}, {"stats", Metrics{{"vertices", double(mesh.num_vertices())}}}},
          {"a warning from the test algorithm"}};
}

CGVIEW_REGISTER_ALGORITHM(test_one_file_coordinate, Params, run,
                          {.title = "Coordinate (test)",
                           .description = "Registered by tests/algorithms/registry/one_file_algorithm.cpp alone.",
                           .area = "tests",
                           .outputs = {{"coordinate", OutputKind::scalar_field}, {"stats", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
