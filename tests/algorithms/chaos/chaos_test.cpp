// Chaotic maps, keyed encryption and steganography: the maps
// against hand computations and known periods; exact round trips, key
// sensitivity, capacity and distortion bounds on sample meshes; the
// registered algorithms' errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <unordered_set>
#include <vector>

#include "chaos/embed.h"
#include "chaos/encrypt.h"
#include "chaos/maps.h"
#include "chaos/measures.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "registry/registry.h"
#include "algorithm_support.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::artifact;
using test::run_algorithm;
using test::Values;

std::vector<Mesh> sample_meshes() {
  std::vector<Mesh> out;
  for (const char* n : {"elephant.off", "bunny00.off", "cube.off", "colored_tetra.ply"})
    out.push_back(read_mesh(test::sample(n)));
  return out;
}

bool bit_equal(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(Vec3)) == 0;
}

// ---- the maps ----------------------------------------------------------

TEST(ChaosMapsTest, IkedaFirstIterateMatchesAHandComputation) {
  // t = 0.4 - 6 / (1 + 1) = -2.6; (1 + 0.9 cos t, 0.9 sin t).
  const chaos::Point2 p = chaos::ikeda_step({1, 0}, 0.9);
  EXPECT_NEAR(p.x, 0.2288001219679474, 1e-15);
  EXPECT_NEAR(p.y, -0.46395123463931776, 1e-15);
  const chaos::Point2 o = chaos::ikeda_step({0, 0}, 0.9);
  EXPECT_DOUBLE_EQ(o.x, 1.0);
  EXPECT_DOUBLE_EQ(o.y, 0.0);
}

TEST(ChaosMapsTest, HenonAndLogisticFirstIterates) {
  const chaos::Point2 h = chaos::henon_step({0.5, 0.2}, 1.4, 0.3);
  EXPECT_DOUBLE_EQ(h.x, 1 - 1.4 * 0.25 + 0.2);
  EXPECT_DOUBLE_EQ(h.y, 0.15);
  EXPECT_DOUBLE_EQ(chaos::logistic_step(0.25, 4.0), 0.75);
}

// The cat map on an N x N grid returns every point after the Pisano period
// of N / 2 steps (N = 5: 10, N = 10: 30, N = 101: 25, N = 2^k: 3 2^(k-2)),
// and not before.
TEST(ChaosMapsTest, CatMapIsPeriodicWithTheKnownPeriod) {
  for (const auto& [n, period] : std::vector<std::pair<std::uint32_t, int>>{{5, 10}, {10, 30}, {101, 25}, {64, 48}}) {
    int first_return = 0;
    for (int step = 1; step <= period && first_return == 0; ++step) {
      bool all_back = true;
      for (std::uint32_t i = 0; i < n && all_back; ++i)
        for (std::uint32_t j = 0; j < n && all_back; ++j) {
          std::array<std::uint32_t, 2> p{i, j};
          for (int s = 0; s < step; ++s) p = chaos::cat_step(p, n);
          all_back = p[0] == i && p[1] == j;
        }
      if (all_back) first_return = step;
    }
    EXPECT_EQ(first_return, period) << "N = " << n;
  }
}

TEST(ChaosMapsTest, CatMapOnAMeshReturnsAfterItsPeriod) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  chaos::MapParams p;
  p.map = chaos::MapKind::cat;
  p.grid = 1024;  // period 768
  const auto start = chaos::apply_map(m.positions, p, 0).positions;
  const auto mid = chaos::apply_map(m.positions, p, 384).positions;
  const auto back = chaos::apply_map(m.positions, p, 768).positions;
  EXPECT_FALSE(bit_equal(start, mid));
  ASSERT_EQ(start.size(), back.size());
  for (std::size_t i = 0; i < start.size(); ++i) EXPECT_NEAR(norm(start[i] - back[i]), 0, 1e-9) << i;
}

TEST(ChaosMapsTest, EveryMapKeepsPositionsFiniteThroughTheRegistry) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  for (const char* map : {"ikeda", "cat", "logistic", "henon", "composite"}) {
    const AlgorithmResult r = run_algorithm("chaos_map", m, {{"map", std::string(map)}, {"steps", 20LL}});
    const Mesh& out = artifact<Mesh>(r, "mesh");
    ASSERT_EQ(out.num_vertices(), m.num_vertices()) << map;
    for (const Vec3& v : out.positions) ASSERT_TRUE(is_finite(v)) << map;
    EXPECT_FALSE(bit_equal(out.positions, m.positions)) << map;
  }
  EXPECT_THROW(run_algorithm("chaos_map", m, {{"map", std::string("tent")}}), InvalidInput);
}

TEST(ChaosMapsTest, StreamDependsOnEveryBitOfTheKey) {
  chaos::ChaoticStream a("d", "secret"), b("d", chaos::flip_one_bit("secret")), c("d", "secret");
  int same = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t x = a.next(), y = b.next();
    EXPECT_EQ(x, c.next());
    same += x == y;
  }
  EXPECT_LT(same, 3);
}

TEST(ChaosAnimateTest, FramesFollowTheMapAndSurviveTheFramesFormat) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const AlgorithmResult r = run_algorithm("chaos_animate", m, {{"map", std::string("ikeda")}, {"frames", 5LL}});
  const Animation& a = artifact<Animation>(r, "animation");
  ASSERT_EQ(a.frames.size(), 5u);
  EXPECT_EQ(a.base.faces, m.faces);
  chaos::MapParams p;
  const BBox box = bounding_box(m);
  for (int k = 1; k <= 5; ++k) {
    const auto expect = chaos::apply_map(m.positions, p, k).positions;
    for (std::size_t i = 0; i < expect.size(); i += 97)
      ASSERT_NEAR(norm(to_double(a.frames[std::size_t(k - 1)][i]) - expect[i]), 0, 1e-5 * box.diagonal());
  }
  const std::string bytes = encode_frames(a);
  EXPECT_EQ(bytes.size(), 44 + 12 * m.num_faces() + 6 * m.num_vertices() * 6);
  const Animation back = decode_frames(bytes);
  ASSERT_EQ(back.frames.size(), 5u);
  EXPECT_EQ(back.base.faces, m.faces);
  BBox all = box;
  for (const auto& f : a.frames)
    for (const Vec3f& v : f) all.add(to_double(v));
  const Vec3 tol = all.size() / 131070.0 + Vec3{1e-6, 1e-6, 1e-6};
  for (std::size_t i = 0; i < m.num_vertices(); i += 13) {
    const Vec3 d = to_double(back.frames[4][i]) - to_double(a.frames[4][i]);
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(d[k]), tol[k]);
  }
  EXPECT_THROW(decode_frames(bytes.substr(0, bytes.size() - 1)), InvalidInput);
}

TEST(ChaosMeasuresTest, HausdorffMatchesBruteForce) {
  const Mesh m = chaos::float32_copy(read_mesh(test::sample("elephant.off")));
  const Mesh c = chaos::encrypt(m, "k");
  std::vector<Vec3> a(m.positions.begin(), m.positions.begin() + 700),
      b(c.positions.begin(), c.positions.begin() + 900);
  auto directed = [](const std::vector<Vec3>& x, const std::vector<Vec3>& y) {
    double worst = 0;
    for (const Vec3& p : x) {
      double best = 1e300;
      for (const Vec3& q : y) best = std::min(best, norm(p - q));
      worst = std::max(worst, best);
    }
    return worst;
  };
  EXPECT_DOUBLE_EQ(chaos::hausdorff_vertices(a, b), std::max(directed(a, b), directed(b, a)));
  EXPECT_DOUBLE_EQ(chaos::hausdorff_vertices(a, a), 0.0);
  const auto r = chaos::adjacent_correlation({{0, 0, 0}, {1, 2, 1}, {2, 4, 0}, {3, 6, 1}});
  EXPECT_NEAR(r[0], 1.0, 1e-12);
  EXPECT_NEAR(r[2], -1.0, 1e-12);
}

// The stream does not fall into a cycle (no 64-bit window of two words comes
// back within 1M words) and its bytes are about uniform.  A clamped
// perturbation once made 3,061 windows repeat here.
TEST(ChaosMapsTest, StreamHasNoShortCycleAndUniformBytes) {
  chaos::ChaoticStream s("d", "key");
  std::unordered_set<std::uint64_t> windows;
  std::vector<double> bytes(256, 0);
  std::uint32_t prev = s.next();
  const int n = 1 << 20;
  int repeats = 0;
  for (int i = 0; i < n; ++i) {
    const std::uint32_t w = s.next();
    repeats += !windows.insert(std::uint64_t(prev) << 32 | w).second;
    for (int b = 0; b < 4; ++b) ++bytes[w >> (8 * b) & 0xFF];
    prev = w;
  }
  EXPECT_EQ(repeats, 0);
  const double expect = 4.0 * n / 256;
  double chi2 = 0;
  for (double c : bytes) chi2 += (c - expect) * (c - expect) / expect;
  EXPECT_GT(chi2, 180);  // 255 degrees of freedom: about p = 0.0002 and 0.9998
  EXPECT_LT(chi2, 345);
}

// ---- encryption ----------------------------------------------------------

TEST(ChaosEncryptTest, RoundTripIsExactOnFloat32CoordinatesOfSampleMeshes) {
  for (const Mesh& m : sample_meshes()) {
    const Mesh cipher = chaos::encrypt(m, "correct horse battery staple");
    EXPECT_EQ(cipher.num_vertices(), m.num_vertices() + 2);
    EXPECT_EQ(cipher.num_faces(), m.num_faces());
    EXPECT_NO_THROW(cipher.validate());
    const Mesh plain = chaos::decrypt(cipher, "correct horse battery staple");
    const Mesh expect = chaos::float32_copy(m);
    EXPECT_TRUE(bit_equal(plain.positions, expect.positions));
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
  EXPECT_TRUE(bit_equal(back.positions, chaos::float32_copy(m).positions));
  write_mesh(cipher, dir / "cipher.obj");
  EXPECT_TRUE(
      bit_equal(chaos::decrypt(read_mesh(dir / "cipher.obj"), "k").positions, chaos::float32_copy(m).positions));
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

TEST(ChaosEncryptTest, RegisteredAlgorithmReportsTheMeasures) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const AlgorithmResult r = run_algorithm("chaos_encrypt", m, {{"key", std::string("k")}});
  const Metrics& x = artifact<Metrics>(r, "metrics");
  EXPECT_EQ(x.at("key_space_bits"), 256);
  EXPECT_EQ(x.at("round_trip_exact"), 1);
  EXPECT_GT(x.at("key_sensitivity_changed_coordinates"), 0.99);
  EXPECT_GT(x.at("hausdorff_vertices_relative"), 0.05);
  const AlgorithmResult d = run_algorithm("chaos_decrypt", artifact<Mesh>(r, "mesh"), {{"key", std::string("k")}});
  EXPECT_TRUE(bit_equal(artifact<Mesh>(d, "mesh").positions, chaos::float32_copy(m).positions));
}

TEST(ChaosEncryptTest, BadInputsNameTheProblem) {
  const Mesh m = test::box();
  try {
    run_algorithm("chaos_encrypt", m, {{"key", std::string("")}});
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'key'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(chaos::encrypt(Mesh{}, "k"), InvalidInput);
  Mesh one;
  one.positions = {{0, 0, 0}};
  EXPECT_THROW(chaos::decrypt(one, "k"), InvalidInput);
}

// ---- steganography -------------------------------------------------------

TEST(ChaosEmbedTest, RoundTripOnSampleMeshesAtEveryWidth) {
  const std::string message = std::string("Figure 11: the Ikeda map on the bunny, \xff") + '\0' + " binary too";
  for (const Mesh& m : sample_meshes())
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
  for (const Mesh& m : sample_meshes()) {
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
    run_algorithm("chaos_embed", m, {{"key", std::string("k")}, {"message", std::string("five!")}, {"bits", 4LL}});
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

TEST(ChaosEmbedTest, RegisteredPairReturnsTheMessageAsText) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const AlgorithmResult e = run_algorithm(
      "chaos_embed", m, {{"key", std::string("k")}, {"message", std::string("hello, mesh")}, {"bits", 2LL}});
  const Metrics& x = artifact<Metrics>(e, "metrics");
  EXPECT_EQ(x.at("capacity_bits_per_vertex"), 6);
  EXPECT_LE(x.at("max_displacement_relative"), x.at("bound_displacement_relative"));
  EXPECT_GT(x.at("snr_db"), 100);
  const AlgorithmResult r = run_algorithm("chaos_extract", artifact<Mesh>(e, "mesh"), {{"key", std::string("k")}});
  EXPECT_EQ(artifact<Text>(r, "message").bytes, "hello, mesh");
  EXPECT_THROW(run_algorithm("chaos_extract", artifact<Mesh>(e, "mesh"), {{"key", std::string("K")}}), InvalidInput);
  // A file's bytes, as base64.
  const AlgorithmResult b = run_algorithm(
      "chaos_embed", m,
      {{"key", std::string("k")}, {"message", std::string("AP8BaGk=")}, {"encoding", std::string("base64")}});
  const AlgorithmResult rb = run_algorithm("chaos_extract", artifact<Mesh>(b, "mesh"), {{"key", std::string("k")}});
  EXPECT_EQ(artifact<Text>(rb, "message").bytes, std::string("\x00\xff\x01hi", 5));
  EXPECT_THROW(
      run_algorithm(
          "chaos_embed", m,
          {{"key", std::string("k")}, {"message", std::string("not*base64")}, {"encoding", std::string("base64")}}),
      InvalidInput);
}

}  // namespace
}  // namespace cgview
