// chaos_decrypt: undoes chaos_encrypt bit for bit with the right key.
#include "chaos/chaos_decrypt.h"

#include <gtest/gtest.h>

#include "chaos/chaos_encrypt.h"
#include "chaos/encrypt.h"
#include "chaos_samples.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosDecryptTest, UndoesChaosEncrypt) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const Mesh cipher = chaos_encrypt(m, {.key = "k", .measure = false}).mesh;
  EXPECT_TRUE(test::bit_equal(chaos_decrypt(cipher, {.key = "k"}).mesh.positions, chaos::float32_copy(m).positions));
}

TEST(ChaosDecryptTest, FewerThanTwoVerticesAreRefused) {
  Mesh one;
  one.positions = {{0, 0, 0}};
  EXPECT_THROW(chaos::decrypt(one, "k"), InvalidInput);
  EXPECT_THROW(chaos_decrypt(one, {.key = "k"}), InvalidInput);
}

}  // namespace
}  // namespace cgview
