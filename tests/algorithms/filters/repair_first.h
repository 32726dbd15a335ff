// The `repair` parameter of the filters that need a halfedge structure
// (filters/repair_mesh.h's halfedge_mesh_for, filters/repair_param.h),
// checked the same way in each filter's test (header-only).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/mesh.h"
#include "core/mesh_report.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "non_manifold_shapes.h"

namespace cgview::test {

// run(mesh, params) calls the filter NAME.  On `broken` (not manifold) with
// its default parameters, a copy is repaired first: a warning says so and
// what changed, the result is manifold and `broken` is left as it was; with
// `repair` off it is refused, naming the filter and the parameter.  Returns
// the result of the default run.
template <class Params, class Run>
auto expect_repaired_by_default(const std::string& name, const Mesh& broken, Run run) {
  EXPECT_FALSE(mesh_report(broken).manifold);
  EXPECT_TRUE(Params{}.repair) << name << ": repair is on by default";
  const Mesh before = broken;
  const auto r = run(broken, Params{});
  expect_same_mesh(broken, before);
  EXPECT_EQ(r.warnings.size(), 1u);
  if (!r.warnings.empty()) {
    EXPECT_EQ(r.warnings[0].rfind(name + ": the mesh was not manifold", 0), 0u) << r.warnings[0];
    EXPECT_NE(r.warnings[0].find("a copy was repaired first: "), std::string::npos) << r.warnings[0];
  }
  EXPECT_GT(r.mesh.num_faces(), 0u);
  EXPECT_TRUE(mesh_report(r.mesh).manifold);
  Params off;
  off.repair = false;
  const std::string what = invalid_input_message([&] { run(broken, off); });
  EXPECT_NE(what.find(name + " needs a manifold mesh"), std::string::npos) << what;
  EXPECT_NE(what.find("set 'repair'"), std::string::npos) << what;
  return r;
}

}  // namespace cgview::test
