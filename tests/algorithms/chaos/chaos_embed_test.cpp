// chaos_embed and its steganography (chaos/embed.h): round trips at every
// width, through the formats that keep float32 values; capacity and
// distortion within the stated bounds; a wrong key fails cleanly; bad inputs.
#include "chaos/chaos_embed.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "chaos/embed.h"
#include "chaos/encrypt.h"
#include "chaos/measures.h"
#include "chaos_samples.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosEmbedTest, RoundTripOnSampleMeshesAtEveryWidth) {
  const std::string message = std::string("Figure 11: the Ikeda map on the bunny, \xff") + '\0' + " binary too";
  for (const Mesh& m : test::chaos_sample_meshes())
    for (int k : {1, 4, 8, 16}) {
      if (chaos::embed_capacity_bytes(m.num_vertices(), k) < message.size()) continue;
      const chaos::EmbedResult e = chaos::embed(m, "stego key", message, k);
      const chaos::ExtractResult x = chaos::extract(e.mesh, "stego key");
      EXPECT_EQ(x.message, message);
      EXPECT_EQ(x.bits, k);
    }
}

TEST(ChaosEmbedTest, MessageSurvivesBinaryPlyAndAWrongKeyFailsCleanly) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  std::string message(2000, '\0');
  for (std::size_t i = 0; i < message.size(); ++i) message[i] = char(i * 7919 % 251);
  const chaos::EmbedResult e = chaos::embed(m, "key", message, 4);
  const auto dir = test::temp_dir("chaos_embed_ply");
  write_mesh(e.mesh, dir / "stego.ply");
  const Mesh back = read_mesh(dir / "stego.ply");
  EXPECT_EQ(chaos::extract(back, "key").message, message);
  // The other formats that keep float32 values and the vertex order (docs/CHAOS.md).
  for (const char* ext : {"obj", "off", "glb"}) {
    write_mesh(e.mesh, dir / (std::string("stego.") + ext));
    EXPECT_EQ(chaos::extract(read_mesh(dir / (std::string("stego.") + ext)), "key").message, message) << ext;
  }
  // Draco quantizes: the message is gone, and extraction says so cleanly.
  write_mesh(e.mesh, dir / "stego.drc");
  EXPECT_THROW(chaos::extract(read_mesh(dir / "stego.drc"), "key"), InvalidInput);
  try {
    chaos::extract(back, chaos::flip_one_bit("key"));
    FAIL() << "a wrong key extracted something";
  } catch (const InvalidInput& err) {
    EXPECT_NE(std::string(err.what()).find("no message found with this key"), std::string::npos);
  }
  EXPECT_THROW(chaos::extract(chaos::float32_copy(m), "key"), InvalidInput);  // no message at all
}

// Capacity 3 k bits per vertex less the header; each vertex moves by at most
// sqrt(3) 2^(k-23) max|coordinate| (docs/CHAOS.md).
TEST(ChaosEmbedTest, CapacityAndDistortionWithinTheStatedBounds) {
  for (const Mesh& m : test::chaos_sample_meshes()) {
    const std::size_t n = m.num_vertices();
    for (int k : {1, 4, 8}) {
      const std::size_t cap = chaos::embed_capacity_bytes(n, k);
      const std::size_t bits = 3 * n * std::size_t(k);
      EXPECT_EQ(cap, bits > 64 ? (bits - 64) / 8 : 0);
      if (cap == 0) continue;
      const std::string message(cap, 'x');  // a full mesh: the worst case
      const chaos::EmbedResult e = chaos::embed(m, "k", message, k);
      double max_abs = 0;
      for (const Vec3& v : m.positions) max_abs = std::max({max_abs, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
      const double bound = std::sqrt(3.0) * std::ldexp(max_abs, k - 23);
      const chaos::Displacement d = chaos::displacement(m.positions, e.mesh.positions);
      EXPECT_LE(d.max, bound) << "k = " << k;
      const double diag = bounding_box(m).diagonal();
      if (k <= 4) {
        EXPECT_LT(d.rms / diag, 1e-5) << "k = " << k;
      }
      EXPECT_EQ(chaos::extract(e.mesh, "k").message, message);
      for (const Vec3& v : e.mesh.positions) ASSERT_TRUE(is_finite(v));
    }
  }
}

TEST(ChaosEmbedTest, MessageLongerThanTheCapacityIsRefused) {
  const Mesh m = test::box();  // 8 vertices: 3 * 8 * 4 = 96 bits, 4 bytes after the header
  EXPECT_EQ(chaos::embed_capacity_bytes(8, 4), 4u);
  EXPECT_NO_THROW(chaos::embed(m, "k", "four", 4));
  try {
    chaos_embed(m, {.key = "k", .message = "five!", .bits = 4});
    FAIL();
  } catch (const InvalidInput& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("'message'"), std::string::npos) << w;
    EXPECT_NE(w.find("5 bytes"), std::string::npos) << w;
    EXPECT_NE(w.find("holds 4 bytes"), std::string::npos) << w;
  }
  EXPECT_THROW(chaos::embed(m, "k", "x", 0), InvalidInput);
  EXPECT_THROW(chaos::embed(m, "", "x", 4), InvalidInput);
}

TEST(ChaosEmbedTest, ReportsTheDistortion) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const ChaosEmbedResult e = chaos_embed(m, {.key = "k", .message = "hello, mesh", .bits = 2});
  EXPECT_EQ(e.metrics.at("capacity_bits_per_vertex"), 6);
  EXPECT_LE(e.metrics.at("max_displacement_relative"), e.metrics.at("bound_displacement_relative"));
  EXPECT_GT(e.metrics.at("snr_db"), 100);
}

TEST(ChaosEmbedTest, Base64MessageOfAnotherCharacterIsRefused) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  EXPECT_THROW(chaos_embed(m, {.key = "k", .message = "not*base64", .encoding = ChaosEmbedEncoding::base64}),
               InvalidInput);
}

}  // namespace
}  // namespace cgview
