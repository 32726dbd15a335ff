// The animation payload of the WebSocket (frames of kind 3): quantized
// deltas, zlib; decoding gives the .frames bytes back exactly, and small
// steps compress better than the frames as they are.
#include "animation_frames.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <string>

#include "core/animation.h"
#include "core/errors.h"
#include "test_support.h"

namespace cgview::protocol {
namespace {

Animation wobbling_sphere(int frames) {
  Animation a;
  a.base = test::uv_sphere(1.0, 24, 48);
  for (int k = 1; k <= frames; ++k) {
    std::vector<Vec3f> p;
    for (const Vec3& v : a.base.positions) {
      const double s = 1 + 0.01 * k * std::sin(3 * v.z);
      p.push_back({float(v.x * s), float(v.y * s), float(v.z)});
    }
    a.frames.push_back(std::move(p));
  }
  return a;
}

std::size_t zlib_size(const std::string& raw) {
  uLongf n = compressBound(uLong(raw.size()));
  std::string out(n, '\0');
  compress2(reinterpret_cast<Bytef*>(out.data()), &n, reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()),
            Z_DEFAULT_COMPRESSION);
  return n;
}

TEST(AnimationPayload, RoundTripsExactlyAndDeltasCompressBetter) {
  const std::string frames = encode_frames(wobbling_sphere(20));
  const std::string payload = encode_animation_payload(frames);
  EXPECT_EQ(decode_animation_payload(payload, frames.size()), frames);
  EXPECT_LT(payload.size(), zlib_size(frames)) << "deltas then zlib beat zlib alone";
  EXPECT_LT(payload.size(), frames.size() / 2);
}

TEST(AnimationPayload, OneFrameAndBadInput) {
  const std::string one = encode_frames(wobbling_sphere(0));
  EXPECT_EQ(decode_animation_payload(encode_animation_payload(one), one.size()), one);
  EXPECT_THROW(encode_animation_payload("not frames"), InvalidInput);
  EXPECT_THROW(encode_animation_payload(one.substr(0, one.size() - 2)), InvalidInput);
  const std::string payload = encode_animation_payload(one);
  EXPECT_THROW(decode_animation_payload(payload.substr(0, payload.size() / 2), one.size()), InvalidInput);
  EXPECT_THROW(decode_animation_payload(payload, one.size() + 1), InvalidInput);
}

}  // namespace
}  // namespace cgview::protocol
