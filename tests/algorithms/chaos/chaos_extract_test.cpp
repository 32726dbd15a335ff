// chaos_extract: the message chaos_embed hid comes back as text, a file's
// bytes (given in base64) as they were; a wrong key is refused.
#include "chaos/chaos_extract.h"

#include <gtest/gtest.h>

#include <string>

#include "chaos/chaos_embed.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosExtractTest, ReturnsTheMessageChaosEmbedHid) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const Mesh stego = chaos_embed(m, {.key = "k", .message = "hello, mesh", .bits = 2}).mesh;
  const ChaosExtractResult r = chaos_extract(stego, {.key = "k"});
  EXPECT_EQ(r.message.bytes, "hello, mesh");
  EXPECT_EQ(r.metrics.at("message_bytes"), 11);
  EXPECT_EQ(r.metrics.at("bits_per_coordinate"), 2);
  EXPECT_THROW(chaos_extract(stego, {.key = "K"}), InvalidInput);
  // A file's bytes, as base64.
  const Mesh b = chaos_embed(m, {.key = "k", .message = "AP8BaGk=", .encoding = ChaosEmbedEncoding::base64}).mesh;
  EXPECT_EQ(chaos_extract(b, {.key = "k"}).message.bytes, std::string("\x00\xff\x01hi", 5));
}

}  // namespace
}  // namespace cgview
