// orient_outward on a box turned inside out (flipped back, face indices
// kept), on one already facing outward and on an open grid (both unchanged).
#include "filters/orient_outward.h"

#include <gtest/gtest.h>

#include <string>

#include "core/mesh_report.h"
#include "core/orient.h"
#include "filter_shapes.h"
#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(OrientOutwardTest, InwardBoxIsTurnedOutward) {
  Mesh inward = test::box();
  flip_faces(inward);
  ASSERT_TRUE(mesh_report(inward).faces_inward);
  const OrientOutwardResult r = orient_outward(inward, {});
  EXPECT_TRUE(r.warnings.empty());
  ASSERT_EQ(r.mesh.num_faces(), inward.num_faces());
  const MeshReport rep = mesh_report(r.mesh);
  EXPECT_FALSE(rep.faces_inward);
  ASSERT_TRUE(rep.volume.has_value());
  EXPECT_NEAR(*rep.volume, 1.0, 1e-9);
  // Each face keeps its index: the same corners, in the other order.
  for (std::size_t f = 0; f < inward.num_faces(); ++f) {
    Tri a = inward.faces[f], b = r.mesh.faces[f];
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    EXPECT_EQ(a, b) << "face " << f;
  }
  EXPECT_EQ(r.metrics.at("faces_flipped"), double(inward.num_faces()));
  EXPECT_NEAR(r.metrics.at("volume_before"), -1.0, 1e-9);
  EXPECT_NEAR(r.metrics.at("volume_after"), 1.0, 1e-9);
}

TEST(OrientOutwardTest, OutwardBoxIsUnchanged) {
  const Mesh box = test::box();
  const OrientOutwardResult r = orient_outward(box);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.mesh.faces, box.faces);
  EXPECT_EQ(r.metrics.at("faces_flipped"), 0.0);
}

TEST(OrientOutwardTest, OpenMeshIsUnchangedWithAWarning) {
  const Mesh g = test::grid(4);
  const OrientOutwardResult r = orient_outward(g);
  EXPECT_EQ(r.mesh.faces, g.faces);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("open: 16 boundary edges"), std::string::npos) << r.warnings[0];
}

TEST(OrientOutwardTest, MeshWithoutFacesIsRefused) {
  EXPECT_NE(test::invalid_input_message([] { orient_outward(Mesh{}); }).find("orient_outward needs a mesh with faces"),
            std::string::npos);
}

}  // namespace
}  // namespace cgview
