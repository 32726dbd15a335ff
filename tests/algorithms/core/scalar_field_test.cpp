// ScalarField: range, normalisation, size checks and face-to-vertex averaging.
#include "core/scalar_field.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/errors.h"
#include "core/mesh.h"
#include "test_support.h"

namespace cgview {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

ScalarField field(std::vector<float> v, Location loc = Location::vertex) {
  return ScalarField{std::string("f"), loc, ColorHint::standard, std::move(v)};
}

TEST(ScalarFieldTest, Range) {
  EXPECT_EQ(field({3, -1, 2, 7.5f}).range(), (std::pair<float, float>{-1, 7.5f}));
  EXPECT_EQ(field({4}).range(), (std::pair<float, float>{4, 4}));
}

TEST(ScalarFieldTest, RangeIgnoresNonFinite) {
  EXPECT_EQ(field({kNaN, 2, kNaN, -3, kInf, -kInf}).range(), (std::pair<float, float>{-3, 2}));
  EXPECT_EQ(field({kNaN, kNaN}).range(), (std::pair<float, float>{0, 0}));
  EXPECT_EQ(field({}).range(), (std::pair<float, float>{0, 0}));
}

TEST(ScalarFieldTest, Normalized) {
  const auto n = field({2, 4, 3, 6}).normalized();
  ASSERT_EQ(n.size(), 4u);
  EXPECT_FLOAT_EQ(n[0], 0.0f);
  EXPECT_FLOAT_EQ(n[1], 0.5f);
  EXPECT_FLOAT_EQ(n[2], 0.25f);
  EXPECT_FLOAT_EQ(n[3], 1.0f);
}

TEST(ScalarFieldTest, NormalizedOverFiniteRange) {
  const auto n = field({kNaN, 10, 20}).normalized();
  ASSERT_EQ(n.size(), 3u);
  EXPECT_TRUE(std::isnan(n[0]));  // a missing value stays missing
  EXPECT_FLOAT_EQ(n[1], 0.0f);
  EXPECT_FLOAT_EQ(n[2], 1.0f);
}

TEST(ScalarFieldTest, NormalizedConstantIsHalf) {
  const auto n = field({5, 5, 5}).normalized();
  EXPECT_EQ(n, (std::vector<float>{0.5f, 0.5f, 0.5f}));
  EXPECT_TRUE(field({}).normalized().empty());
}

std::string mismatch_message(const ScalarField& f, const Mesh& m) {
  try {
    f.check_matches(m);
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(ScalarFieldTest, CheckMatches) {
  const Mesh m = test::box();  // 8 vertices, 12 faces
  EXPECT_NO_THROW(field(std::vector<float>(8, 0)).check_matches(m));
  EXPECT_NO_THROW(field(std::vector<float>(12, 0), Location::face).check_matches(m));
  EXPECT_THROW(field(std::vector<float>(12, 0)).check_matches(m), InvalidInput);
  EXPECT_THROW(field(std::vector<float>(8, 0), Location::face).check_matches(m), InvalidInput);
  EXPECT_THROW(field({}).check_matches(m), InvalidInput);
}

TEST(ScalarFieldTest, CheckMatchesMessage) {
  const Mesh m = test::box();
  ScalarField f = field(std::vector<float>(5, 0));
  f.name = "curvature";
  std::string msg = mismatch_message(f, m);
  EXPECT_EQ(msg, "scalar field 'curvature' has 5 values but the mesh has 8 vertices");

  f.location = Location::face;
  msg = mismatch_message(f, m);
  EXPECT_EQ(msg, "scalar field 'curvature' has 5 values but the mesh has 12 faces");

  Mesh one;
  one.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  one.faces = {{0, 1, 2}};
  msg = mismatch_message(f, one);
  EXPECT_EQ(msg, "scalar field 'curvature' has 5 values but the mesh has 1 face");
}

TEST(ScalarFieldTest, FaceToVertexConstantStaysConstant) {
  const Mesh m = test::uv_sphere(1.0, 8, 16);
  ScalarField f = field(std::vector<float>(m.num_faces(), 2.5f), Location::face);
  f.name = "c";
  f.hint = ColorHint::magnitude;
  const ScalarField v = face_to_vertex(m, f);
  EXPECT_EQ(v.location, Location::vertex);
  EXPECT_EQ(v.name, "c");
  EXPECT_EQ(v.hint, ColorHint::magnitude);
  ASSERT_EQ(v.values.size(), m.num_vertices());
  for (float x : v.values) EXPECT_NEAR(x, 2.5f, 1e-6f);
}

TEST(ScalarFieldTest, FaceToVertexWeightsByArea) {
  // Vertex 0 is shared by a face of area 0.5 (value 1) and one of area 2
  // (value 6): (0.5 * 1 + 2 * 6) / 2.5 = 5.  Vertex 5 is used by no face.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-2, 0, 0}, {0, -2, 0}, {9, 9, 9}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  const ScalarField v = face_to_vertex(m, field({1, 6}, Location::face));
  ASSERT_EQ(v.values.size(), 6u);
  EXPECT_FLOAT_EQ(v.values[0], 5.0f);
  EXPECT_FLOAT_EQ(v.values[1], 1.0f);
  EXPECT_FLOAT_EQ(v.values[2], 1.0f);
  EXPECT_FLOAT_EQ(v.values[3], 6.0f);
  EXPECT_FLOAT_EQ(v.values[4], 6.0f);
  EXPECT_FLOAT_EQ(v.values[5], 0.0f);
}

TEST(ScalarFieldTest, FaceToVertexOnGrid) {
  // grid(1): face 0 and face 1 each of area 0.5; the diagonal's ends get the
  // average, the other corners their own face's value.
  const Mesh m = test::grid(1);
  const ScalarField v = face_to_vertex(m, field({0, 10}, Location::face));
  ASSERT_EQ(v.values.size(), 4u);
  EXPECT_FLOAT_EQ(v.values[0], 5.0f);   // (0,0): both faces
  EXPECT_FLOAT_EQ(v.values[1], 0.0f);   // (1,0): face 0 only
  EXPECT_FLOAT_EQ(v.values[2], 10.0f);  // (0,1): face 1 only
  EXPECT_FLOAT_EQ(v.values[3], 5.0f);   // (1,1): both faces
}

TEST(ScalarFieldTest, FaceToVertexRejectsBadInput) {
  const Mesh m = test::box();
  EXPECT_THROW(face_to_vertex(m, field(std::vector<float>(8, 0))), InvalidInput);  // per vertex
  EXPECT_THROW(face_to_vertex(m, field(std::vector<float>(11, 0), Location::face)), InvalidInput);
}

TEST(ScalarFieldTest, Names) {
  EXPECT_STREQ(to_string(Location::vertex), "vertex");
  EXPECT_STREQ(to_string(Location::face), "face");
  EXPECT_STREQ(to_string(ColorHint::standard), "standard");
  EXPECT_STREQ(to_string(ColorHint::symmetric), "symmetric");
  EXPECT_STREQ(to_string(ColorHint::magnitude), "magnitude");
  EXPECT_STREQ(to_string(ColorHint::categorical), "categorical");
}

}  // namespace
}  // namespace cgview
