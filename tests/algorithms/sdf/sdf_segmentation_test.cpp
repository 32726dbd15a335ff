// sdf_segmentation: the elephant's parts, cluster ids, bad input.
#include "sdf/sdf_segmentation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(SdfSegmentation, GivesLabelledPartsAsCategories) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const sdf::SdfSegmentationResult res = sdf::sdf_segmentation(mesh, {.clusters = 4});
  const ScalarField& seg = res.segments;
  EXPECT_EQ(seg.hint, ColorHint::categorical);
  ASSERT_EQ(seg.values.size(), mesh.faces.size());
  const double count = res.metrics.at("segments");
  EXPECT_GE(count, 4);  // body, legs, trunk, ears: parts of several SDF levels
  for (float v : seg.values) {
    ASSERT_EQ(v, std::floor(v));
    ASSERT_LT(v, count);
  }
  // Cluster ids instead: at most `clusters` distinct values.
  const sdf::SdfSegmentationResult clusters = sdf::sdf_segmentation(mesh, {.clusters = 4, .cluster_ids = true});
  EXPECT_LE(clusters.segments.range().second, 3.0f);
}

TEST(SdfSegmentationBadInput, ClearErrors) {
  Mesh no_faces;
  no_faces.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(sdf::sdf_segmentation(no_faces), InvalidInput);
  // Segmentation needs a manifold mesh: three faces on one edge are refused.
  Mesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  EXPECT_THROW(sdf::sdf_segmentation(fin), InvalidInput);
}

}  // namespace
}  // namespace cgview
