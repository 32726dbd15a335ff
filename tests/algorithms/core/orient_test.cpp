// orient_outward: a closed mesh facing inward is turned as CGAL's
// orient_to_bound_a_volume turns it (the reference), face indices kept;
// what already faces outward, a hollow shell, and an open mesh are left.
#include "core/orient.h"

#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>

#include <cmath>
#include <numbers>

#include "core/mesh_report.h"
#include "core/surface_mesh.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using test::merged;
using test::uv_sphere;

Mesh flipped(Mesh m) {
  flip_faces(m);
  return m;
}

TEST(Orient, AnInwardSphereIsReportedAndTurnedAsCgalTurnsIt) {
  const Mesh out = uv_sphere(2.0, 24, 48);
  const Mesh in = flipped(out);
  const MeshReport r = mesh_report(in);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);  // consistently: all the wrong way
  EXPECT_TRUE(r.faces_inward);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_LT(*r.volume, 0);
  EXPECT_FALSE(mesh_report(out).faces_inward);

  Mesh turned = in;
  EXPECT_TRUE(orient_outward_in_place(turned));
  // CGAL's answer on the same inward mesh.
  SurfaceMesh reference = to_surface_mesh(in).mesh;
  PMP::orient_to_bound_a_volume(reference);
  const double cgal_volume = PMP::volume(reference);
  EXPECT_NEAR(*mesh_report(turned).volume, cgal_volume, 1e-9 * cgal_volume);
  EXPECT_NEAR(cgal_volume, 4.0 / 3.0 * std::numbers::pi * 8, 0.02 * cgal_volume);  // the analytic ball, nearly
  // Face for face the outward sphere: same vertices, each face as it was made.
  ASSERT_EQ(turned.faces.size(), out.faces.size());
  for (std::size_t f = 0; f < out.faces.size(); ++f) {
    const Vec3 a = face_cross(turned, f), b = face_cross(out, f);
    ASSERT_GT(dot(a, b), 0) << "face " << f;
  }
}

TEST(Orient, AHollowShellOpenMeshAndOutwardMeshAreLeftAsTheyAre) {
  // A ball with a cavity: the inner sphere faces into the hollow, rightly.
  const Mesh hollow = merged(uv_sphere(2.0), flipped(uv_sphere(1.0)));
  EXPECT_FALSE(mesh_report(hollow).faces_inward);
  Mesh h = hollow;
  EXPECT_FALSE(orient_outward_in_place(h));
  EXPECT_EQ(h.faces, hollow.faces);
  // Inward as a whole, it is turned as a whole: the cavity faces in again.
  Mesh inverted = flipped(hollow);
  EXPECT_TRUE(orient_outward_in_place(inverted));
  EXPECT_EQ(inverted.faces, hollow.faces);

  Mesh open = flipped(uv_sphere(1.0));
  open.faces.pop_back();
  EXPECT_FALSE(mesh_report(open).faces_inward);  // no inside to face
  const auto before = open.faces;
  EXPECT_FALSE(orient_outward_in_place(open));
  EXPECT_EQ(open.faces, before);
}

}  // namespace
}  // namespace cgview
