// skeleton_metrics: the measures of a skeleton against its mesh, as an
// algorithm of two inputs (skeleton_measures_test.cpp tests the measures).
#include "skeleton/skeleton_metrics.h"

#include <gtest/gtest.h>

#include "algorithm_support.h"
#include "skeleton_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::circle;
using test::run_algorithm;

TEST(SkeletonMetrics, CircleInsideATorusAsAMetricsTable) {
  const double R = 2, r = 0.5;
  const Metrics m = skeleton_metrics(test::torus(R, r, 96, 32), circle(R, 64)).metrics;
  EXPECT_EQ(m.at("loops"), 1.0);
  EXPECT_EQ(m.at("endpoints"), 0.0);
  EXPECT_EQ(m.at("inside_fraction"), 1.0);
  EXPECT_EQ(m.at("centredness_nodes"), 64.0);
}

// A job names its inputs: one missing is refused before the run.
TEST(SkeletonMetrics, ASkeletonMustBeGiven) {
  Inputs in;
  const Mesh sphere = test::uv_sphere();
  in.add("mesh", sphere);
  EXPECT_THROW(run_algorithm("skeleton_metrics", in), InvalidInput);  // no skeleton given
}

}  // namespace
}  // namespace cgview
