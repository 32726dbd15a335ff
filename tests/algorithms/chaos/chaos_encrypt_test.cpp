// chaos_encrypt and its cipher (chaos/encrypt.h): exact round trips on
// float32 coordinates, through files too; key sensitivity; decorrelation;
// the metrics it reports; bad inputs.
#include "chaos/chaos_encrypt.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "chaos/encrypt.h"
#include "chaos/measures.h"
#include "chaos_samples.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosEncryptTest, RoundTripIsExactOnFloat32CoordinatesOfSampleMeshes) {
  for (const Mesh& m : test::chaos_sample_meshes()) {
    const Mesh cipher = chaos::encrypt(m, "correct horse battery staple");
    EXPECT_EQ(cipher.num_vertices(), m.num_vertices() + 2);
    EXPECT_EQ(cipher.num_faces(), m.num_faces());
    EXPECT_NO_THROW(cipher.validate());
    const Mesh plain = chaos::decrypt(cipher, "correct horse battery staple");
    const Mesh expect = chaos::float32_copy(m);
    EXPECT_TRUE(test::bit_equal(plain.positions, expect.positions));
    EXPECT_EQ(plain.faces, expect.faces);
  }
}

TEST(ChaosEncryptTest, SurvivesBinaryPlyAndKeepsSignedZerosAndDenormals) {
  Mesh m = test::box({-1, -1, -1}, {1, 1, 1});
  m.positions[0] = {-0.0, 0.0, 1e-40};  // a negative zero and a float32 denormal
  m.positions[1] = {std::ldexp(1.0, -149), -0.0, 0.5};
  const Mesh cipher = chaos::encrypt(m, "k");
  const auto dir = test::temp_dir("chaos_encrypt_ply");
  write_mesh(cipher, dir / "cipher.ply");
  const Mesh back = chaos::decrypt(read_mesh(dir / "cipher.ply"), "k");
  EXPECT_TRUE(test::bit_equal(back.positions, chaos::float32_copy(m).positions));
  write_mesh(cipher, dir / "cipher.obj");
  EXPECT_TRUE(
      test::bit_equal(chaos::decrypt(read_mesh(dir / "cipher.obj"), "k").positions, chaos::float32_copy(m).positions));
  EXPECT_TRUE(std::signbit(back.positions[0].x));
  EXPECT_EQ(back.faces, m.faces);
}

TEST(ChaosEncryptTest, OneBitOffInTheKeyGivesAnUnrecognizableMesh) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  const Mesh cipher = chaos::encrypt(m, "key0");
  const Mesh wrong = chaos::decrypt(cipher, chaos::flip_one_bit("key0"));
  const Mesh plain = chaos::float32_copy(m);
  EXPECT_GT(chaos::changed_share(plain.positions, wrong.positions), 0.99);
  std::size_t same_faces = 0;
  for (std::size_t f = 0; f < m.num_faces(); ++f) same_faces += wrong.faces[f] == plain.faces[f];
  EXPECT_LT(double(same_faces) / double(m.num_faces()), 0.01);
  const double diag = bounding_box(plain).diagonal();
  EXPECT_GT(chaos::hausdorff_vertices(plain.positions, wrong.positions) / diag, 0.05);
  // Two encryptions with keys one bit apart differ almost everywhere.
  const Mesh other = chaos::encrypt(m, chaos::flip_one_bit("key0"));
  EXPECT_GT(chaos::changed_share(cipher.positions, other.positions), 0.99);
}

TEST(ChaosEncryptTest, CipherDecorrelatesAdjacentCoordinatesAndStaysInTheBox) {
  const Mesh m = chaos::float32_copy(read_mesh(test::sample("elephant.off")));
  const Mesh cipher = chaos::encrypt(m, "key");
  const auto before = chaos::adjacent_correlation(m.positions);
  const auto after = chaos::adjacent_correlation(cipher.positions);
  const BBox box = bounding_box(m), cbox = bounding_box(cipher);
  for (int a = 0; a < 3; ++a) {
    EXPECT_GT(before[std::size_t(a)], 0.5) << a;  // mesh vertex orders are spatially coherent
    EXPECT_LT(std::abs(after[std::size_t(a)]), 0.05) << a;
    EXPECT_EQ(cbox.min[a], box.min[a]);
    EXPECT_EQ(cbox.max[a], box.max[a]);
  }
}

TEST(ChaosEncryptTest, ReportsTheMeasures) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const Metrics x = chaos_encrypt(m, {.key = "k"}).metrics;
  EXPECT_EQ(x.at("key_space_bits"), 256);
  EXPECT_EQ(x.at("round_trip_exact"), 1);
  EXPECT_GT(x.at("key_sensitivity_changed_coordinates"), 0.99);
  EXPECT_GT(x.at("hausdorff_vertices_relative"), 0.05);
}

TEST(ChaosEncryptTest, BadInputsNameTheProblem) {
  const Mesh m = test::box();
  try {
    chaos_encrypt(m, {.key = ""});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'key'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(chaos::encrypt(Mesh{}, "k"), InvalidInput);
}

}  // namespace
}  // namespace cgview
