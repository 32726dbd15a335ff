// The `repair` parameter of the filters that need a halfedge structure
// (filters/repair_mesh.h's halfedge_mesh_for), checked the same way in each
// filter's test (header-only).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/mesh.h"
#include "core/mesh_report.h"
#include "filter_shapes.h"
#include "invalid_input.h"

namespace cgview::test {

// run(repair) calls the filter NAME on sphere_with_a_fin() with its `repair`
// parameter: refused without it, naming the filter and the parameter; with
// it, the mesh is repaired first, with a warning, and the result is manifold.
template <class Run>
void expect_refused_or_repaired_first(const std::string& name, Run run) {
  ASSERT_FALSE(mesh_report(sphere_with_a_fin()).manifold);
  const std::string what = invalid_input_message([&] { run(false); });
  EXPECT_NE(what.find(name + " needs a manifold mesh"), std::string::npos) << what;
  EXPECT_NE(what.find("set 'repair'"), std::string::npos) << what;
  const auto r = run(true);
  ASSERT_FALSE(r.warnings.empty());
  EXPECT_NE(r.warnings[0].find("repaired first"), std::string::npos) << r.warnings[0];
  EXPECT_GT(r.mesh.num_faces(), 0u);
  EXPECT_TRUE(mesh_report(r.mesh).manifold);
}

}  // namespace cgview::test
