// Embree's ray caster (rays/ray_caster.h): what a hit says about the face it
// met, against the mesh's own normals (face_normals, in double).
#include "rays/ray_caster.h"

#include <gtest/gtest.h>

#include <random>

#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

// The SDF tells a ray leaving the shape from one entering it by the hit's
// normal alone: it must face as the face's own normal does.
TEST(RayCaster, AHitCarriesTheNormalOfTheFaceItMet) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const RayCaster caster(mesh);
  const std::vector<Vec3> normals = face_normals(mesh);
  const BBox box = bounding_box(mesh);
  std::mt19937 rng(11);
  std::normal_distribution<double> gauss;
  std::size_t hits = 0, inward = 0;
  for (std::size_t f = 0; f < mesh.faces.size(); f += 7) {
    const Vec3 c = face_centroid(mesh, f);
    const Vec3 d = -1.0 * normals[f] + 0.4 * normalized(Vec3{gauss(rng), gauss(rng), gauss(rng)});
    const RayCaster::Hit h = caster.first_hit(c, d, std::uint32_t(f));
    if (!h) continue;
    ++hits;
    ASSERT_GT(norm(h.normal), 0) << "face " << h.face;
    EXPECT_GT(dot(normalized(h.normal), normals[h.face]), 1 - 1e-5) << "face " << h.face;
    inward += dot(d, h.normal) > 0;  // met from behind: the ray leaves the shape there
  }
  EXPECT_GT(hits, mesh.faces.size() / 7 / 2);
  EXPECT_GT(inward, hits * 9 / 10);  // a closed mesh: most rays into it leave it where they first meet it
  // From outside, along an axis through the box's centre: met from in front.
  const RayCaster::Hit outside = caster.first_hit(box.center() - Vec3{box.diagonal(), 0, 0}, {1, 0, 0});
  ASSERT_TRUE(outside);
  EXPECT_LT(outside.normal.x, 0);
}

}  // namespace
}  // namespace cgview
