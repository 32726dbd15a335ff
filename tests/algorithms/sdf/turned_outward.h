// The check that an SDF algorithm's job turns a mesh facing inward outward
// for its run (the registry's InputSpec::outward, kSdfInput) and says so:
// the same values as on the mesh facing outward, and a warning.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "algorithm_support.h"
#include "core/orient.h"
#include "test_support.h"

namespace cgview::test {

inline void expect_turned_outward(const std::string& algorithm, const std::string& field) {
  // The rays go along the inward normal: facing inward they would leave
  // the ball, and most faces would have no value.
  const Mesh out = uv_sphere(1.0, 16, 32);
  Mesh in = out;
  flip_faces(in);
  const AlgorithmResult a = run_algorithm(algorithm, out, {{"smooth", false}});
  const AlgorithmResult b = run_algorithm(algorithm, in, {{"smooth", false}});
  const ScalarField& fa = artifact<ScalarField>(a, field);
  const ScalarField& fb = artifact<ScalarField>(b, field);
  ASSERT_EQ(fa.values.size(), fb.values.size());
  for (std::size_t f = 0; f < fa.values.size(); ++f) ASSERT_FLOAT_EQ(fa.values[f], fb.values[f]) << "face " << f;
  EXPECT_TRUE(a.warnings.empty() || a.warnings.front().find("face inward") == std::string::npos);
  ASSERT_FALSE(b.warnings.empty());
  EXPECT_NE(b.warnings.front().find("faces all face inward"), std::string::npos) << b.warnings.front();
  EXPECT_NE(b.warnings.front().find("turned outward"), std::string::npos);
}

}  // namespace cgview::test
