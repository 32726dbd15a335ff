// sdf_segmentation: the elephant's parts, CGAL's own segmentation, cluster ids,
// bad input.
#include "sdf/sdf_segmentation.h"

#include <CGAL/mesh_segmentation.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include "core/surface_mesh.h"
#include "filters/repair.h"
#include "io/mesh_io.h"
#include "non_manifold_shapes.h"
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

// With CGAL's weights and outlier rule our SDF is CGAL's (sdf_rays_test.cpp),
// so the segments are those of CGAL's own segmentation_via_sdf_values, which
// casts its own rays on one thread: the same segment on every face but a
// grazing ray's (all 5558 measured; rays whose cone turned with each face's
// first edge left 9 faces in another segment).
TEST(SdfSegmentation, IsCgalsSegmentationViaSdfValuesWithCgalsRule) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const sdf::SdfSegmentationResult ours = sdf::sdf_segmentation(
      mesh, {.clusters = 5, .sdf = {.weights = sdf::Weights::uniform, .outliers = sdf::Outliers::mad}});
  SurfaceMesh sm = manifold_surface_mesh(mesh, "the CGAL reference");
  auto segment = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:segment", 0).first;
  const std::size_t segments = CGAL::segmentation_via_sdf_values(sm, segment, 2.0 * std::numbers::pi / 3.0, 25, 5);
  EXPECT_EQ(ours.metrics.at("segments"), double(segments));
  std::size_t same = 0;
  for (SurfaceMesh::Face_index f : sm.faces()) same += ours.segments.values[std::size_t(f)] == float(segment[f]);
  std::printf("%zu segments; %zu of %zu faces in the same one as CGAL's\n", segments, same, mesh.faces.size());
  EXPECT_GE(double(same), 0.9995 * double(mesh.faces.size()));
}

TEST(SdfSegmentationBadInput, ClearErrors) {
  Mesh no_faces;
  no_faces.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_THROW(sdf::sdf_segmentation(no_faces), InvalidInput);
  // With repair off, segmentation needs a manifold mesh: three faces on one
  // edge are refused.
  Mesh fin;
  fin.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  fin.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  try {
    sdf::sdf_segmentation(fin, {.repair = false});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("sdf_segmentation needs a manifold mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("set 'repair'"), std::string::npos) << e.what();
  }
}

// Two spheres on one vertex, a face given twice and a degenerate one: by
// default the cut runs on a repaired copy, where the spheres are apart (no
// segment spans both), with one segment per face of the input (the
// degenerate one a neighbour's); as CGAL cuts the repair filter's mesh with
// repair off, face for face (found by their corners).
TEST(SdfSegmentation, NonManifoldMeshIsCutOnARepairedCopyByDefault) {
  EXPECT_TRUE(sdf::SdfSegmentationParams{}.repair);
  Mesh broken = test::two_spheres_touching();
  const std::size_t half = broken.faces.size() / 2;  // the lower sphere's faces, then the upper's
  broken.faces.push_back(broken.faces[5]);
  const Tri f7 = broken.faces[7];
  broken.faces.push_back({f7[0], f7[1], f7[0]});  // degenerate, on face 7's first edge
  const Mesh before = broken;
  const sdf::SdfSegmentationResult r = sdf::sdf_segmentation(broken);
  test::expect_same_mesh(broken, before);
  ASSERT_GE(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].rfind("sdf_segmentation: the mesh was not manifold", 0), 0u) << r.warnings[0];
  EXPECT_NE(r.warnings[0].find("a copy was repaired first: 1 vertex duplicated to split non-manifold edges and "
                               "vertices, 2 degenerate or duplicate faces removed"),
            std::string::npos)
      << r.warnings[0];
  const std::vector<float>& seg = r.segments.values;
  ASSERT_EQ(seg.size(), broken.faces.size());
  const std::size_t twice = broken.faces.size() - 2, degenerate = twice + 1;
  EXPECT_EQ(seg[twice], seg[5]);
  std::set<float> lower(seg.begin(), seg.begin() + std::ptrdiff_t(half)),
      upper(seg.begin() + std::ptrdiff_t(half), seg.begin() + std::ptrdiff_t(twice));
  // The degenerate face's segment: that of a face on its edge.
  std::set<float> beside;
  for (std::size_t f = 0; f < twice; ++f) {
    const Tri& t = broken.faces[f];
    if (std::count(t.begin(), t.end(), f7[0]) + std::count(t.begin(), t.end(), f7[1]) == 2) beside.insert(seg[f]);
  }
  EXPECT_EQ(beside.count(seg[degenerate]), 1u);
  for (float id : lower) EXPECT_EQ(upper.count(id), 0u) << "segment " << id << " spans both spheres";
  EXPECT_EQ(r.metrics.at("segments"), double(lower.size() + upper.size()));

  const Mesh repaired = repair(broken).mesh;
  const sdf::SdfSegmentationResult ref = sdf::sdf_segmentation(repaired, {.repair = false});
  auto corners = [](const Mesh& m, const Tri& t) {
    std::array<std::array<double, 3>, 3> c{};
    for (int k = 0; k < 3; ++k) c[k] = {m.positions[t[k]].x, m.positions[t[k]].y, m.positions[t[k]].z};
    std::sort(c.begin(), c.end());
    return c;
  };
  std::map<std::array<std::array<double, 3>, 3>, float> ref_of;
  for (std::size_t f = 0; f < repaired.faces.size(); ++f)
    ref_of[corners(repaired, repaired.faces[f])] = ref.segments.values[f];
  ASSERT_EQ(ref_of.size(), broken.faces.size() - 2);
  // CGAL numbers the segments by their mean SDF, which for two equal
  // spheres is a tie that rounding decides: the same cut is the same
  // segments under one-to-one names.
  std::map<float, float> name_in_ref, name_here;
  for (std::size_t f = 0; f < twice; ++f) {
    const auto it = ref_of.find(corners(broken, broken.faces[f]));
    ASSERT_NE(it, ref_of.end()) << "face " << f;
    EXPECT_EQ(name_in_ref.try_emplace(seg[f], it->second).first->second, it->second) << "face " << f;
    EXPECT_EQ(name_here.try_emplace(it->second, seg[f]).first->second, seg[f]) << "face " << f;
  }
  EXPECT_EQ(r.metrics.at("segments"), ref.metrics.at("segments"));
}

}  // namespace
}  // namespace cgview
