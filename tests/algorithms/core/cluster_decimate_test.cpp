// cluster_decimate: the triangle count is within the target, the bounding box
// is kept within one cell, no face is degenerate, colours are averaged; over
// generated shapes and the sample family.
#include "core/cluster_decimate.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

// The invariants of any decimation to `target` faces.
void check(const Mesh& in, std::size_t target, const std::string& what) {
  SCOPED_TRACE(what);
  const ClusterDecimateResult r = cluster_decimate(in, {target});
  const Mesh& out = r.mesh;
  EXPECT_NO_THROW(out.validate());
  EXPECT_LE(out.num_faces(), target);
  if (in.num_faces() <= target) {
    EXPECT_EQ(out.num_faces(), in.num_faces());
    return;
  }
  // Not over-decimated: a closed-ish shape keeps a good part of its budget.
  EXPECT_GE(out.num_faces(), target / 5);
  EXPECT_GT(r.cell_size, 0.0);
  const BBox a = bounding_box(in), b = bounding_box(out);
  for (int k = 0; k < 3; ++k) {
    EXPECT_GE(b.min[k], a.min[k] - 1e-9);
    EXPECT_LE(b.max[k], a.max[k] + 1e-9);
    EXPECT_LE(b.min[k] - a.min[k], r.cell_size) << "axis " << k;
    EXPECT_LE(a.max[k] - b.max[k], r.cell_size) << "axis " << k;
  }
  const std::vector<double> areas = face_areas(out);
  for (std::size_t f = 0; f < out.num_faces(); ++f) {
    const Tri& t = out.faces[f];
    ASSERT_TRUE(t[0] != t[1] && t[1] != t[2] && t[2] != t[0]) << "face " << f;
    ASSERT_GT(areas[f], 0.0) << "face " << f;
  }
  // Every vertex is used by a face.
  std::vector<char> used(out.num_vertices(), 0);
  for (const Tri& t : out.faces)
    for (Index v : t) used[v] = 1;
  EXPECT_EQ(std::count(used.begin(), used.end(), 0), 0);
}

TEST(ClusterDecimate, SphereToAFraction) {
  const Mesh s = test::uv_sphere(1.0, 200, 400);  // ~160k faces
  ASSERT_GT(s.num_faces(), 100000u);
  for (std::size_t target : {50000u, 5000u, 500u}) check(s, target, "sphere to " + std::to_string(target));
}

TEST(ClusterDecimate, SubdividedTorusKeepsItsShape) {
  Mesh t = subdivide_midpoint(subdivide_midpoint(test::torus(2.0, 0.5, 48, 24)));
  check(t, 4000, "torus");
  // Its vertices stay near the torus surface: within a cell of it.
  const ClusterDecimateResult r = cluster_decimate(t, {4000});
  for (const Vec3& p : r.mesh.positions) {
    const double ring = std::hypot(p.x, p.y) - 2.0;
    EXPECT_NEAR(std::hypot(ring, p.z), 0.5, r.cell_size);
  }
}

TEST(ClusterDecimate, SmallMeshIsCopied) {
  const Mesh b = test::box();
  const ClusterDecimateResult r = cluster_decimate(b, {100});
  EXPECT_EQ(r.mesh.faces, b.faces);
  EXPECT_EQ(r.cell_size, 0.0);
}

TEST(ClusterDecimate, ColoursAreAveraged) {
  Mesh s = test::uv_sphere(1.0, 60, 120);
  s.colors.assign(s.num_vertices(), Color{200, 100, 50, 255});
  const ClusterDecimateResult r = cluster_decimate(s, {1000});
  ASSERT_EQ(r.mesh.colors.size(), r.mesh.num_vertices());
  for (const Color& c : r.mesh.colors) EXPECT_EQ(c, (Color{200, 100, 50, 255}));
}

TEST(ClusterDecimate, BadInput) {
  EXPECT_THROW(cluster_decimate(test::box(), {0}), InvalidInput);
  Mesh bad = test::box();
  bad.faces[0][0] = 99;
  EXPECT_THROW(cluster_decimate(bad, {1}), InvalidInput);
}

TEST(ClusterDecimate, SampleFamily) {
  for (const auto& path : test::sample_family()) {
    const Mesh m = read_mesh(path);
    if (m.num_faces() < 400) continue;
    check(m, m.num_faces() / 4, path.filename().string());
  }
}

}  // namespace
}  // namespace cgview
