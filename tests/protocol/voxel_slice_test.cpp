// Voxel-slice payloads (API.md, protocol/voxel_slice.h): the header read by
// its documented offsets, the values inflated with zlib directly.
#include "voxel_slice.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>

#include "core/errors.h"
#include "frames.h"

namespace cgview::protocol {
namespace {

template <class T>
T at(const std::string& s, std::size_t o) {
  T v;
  std::memcpy(&v, s.data() + o, sizeof v);
  return v;
}

TEST(VoxelSliceTest, PayloadFollowsTheDocumentedLayout) {
  VoxelGrid g({6, 5, 4}, {1, 2, 3}, 0.5, VoxelType::uint8);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i) g.set({i, j, 2}, float(i + 10 * j));
  const VoxelSlice s = slice(g, 2, 2);
  const std::string p = encode_slice_payload(g, s);
  ASSERT_EQ(p.substr(0, 4), "CGVS");
  EXPECT_EQ(at<std::uint16_t>(p, 4), 1);
  EXPECT_EQ(at<std::uint8_t>(p, 6), 2);  // z
  EXPECT_EQ(at<std::uint8_t>(p, 7), 1);  // uint8
  EXPECT_EQ(at<std::uint32_t>(p, 8), 2u);
  EXPECT_EQ(at<std::uint32_t>(p, 12), 6u);
  EXPECT_EQ(at<std::uint32_t>(p, 16), 5u);
  EXPECT_EQ(at<std::uint32_t>(p, 20), 1u);  // zlib
  EXPECT_EQ(at<std::uint32_t>(p, 24), 30u);
  EXPECT_EQ(at<std::uint32_t>(p, 28), p.size() - 64);
  EXPECT_EQ(at<double>(p, 32), 0.5);
  EXPECT_EQ(at<double>(p, 40), 1.0);
  EXPECT_EQ(at<double>(p, 48), 2.0);
  EXPECT_EQ(at<double>(p, 56), 4.0);  // 3 + 2 * 0.5: the slice's corner along z
  std::string raw(30, '\0');
  uLongf n = 30;
  ASSERT_EQ(uncompress(reinterpret_cast<Bytef*>(raw.data()), &n, reinterpret_cast<const Bytef*>(p.data() + 64),
                       uLong(p.size() - 64)),
            Z_OK);
  for (int j = 0; j < 5; ++j)
    for (int i = 0; i < 6; ++i) EXPECT_EQ(std::uint8_t(raw[std::size_t(i + 6 * j)]), i + 10 * j);
  const DecodedSlice d = decode_slice_payload(p);
  EXPECT_EQ(d.slice.values, s.values);
  EXPECT_FALSE(d.floats);
  // In frames of kind 2.
  const auto frames = split_into_frames(p, FrameKind::voxel_slice, 7, 16);
  std::string joined;
  for (const auto& f : frames) {
    std::string_view chunk;
    const std::string frame = f.bytes();
    EXPECT_EQ(decode_frame(frame, &chunk).kind, FrameKind::voxel_slice);
    joined += chunk;
  }
  EXPECT_EQ(joined, p);
}

TEST(VoxelSliceTest, FloatSlicesAndBadPayloads) {
  VoxelGrid g({3, 4, 5}, {0, 0, 0}, 1.0, VoxelType::float32);
  g.set({1, 2, 3}, 0.25f);
  const VoxelSlice s = slice(g, 0, 1);
  EXPECT_EQ(s.width, 4);
  EXPECT_EQ(s.height, 5);
  const std::string p = encode_slice_payload(g, s);
  EXPECT_EQ(at<std::uint8_t>(p, 7), 2);
  const DecodedSlice d = decode_slice_payload(p);
  EXPECT_TRUE(d.floats);
  EXPECT_EQ(d.slice.values[2 + 4 * 3], 0.25f);
  EXPECT_THROW(decode_slice_payload("CGVS"), InvalidInput);
  std::string bad = p;
  bad[p.size() - 3] ^= 0x55;
  EXPECT_THROW(decode_slice_payload(bad), InvalidInput);
  bad = p;
  bad[12] = 9;  // width no longer matches the raw size
  EXPECT_THROW(decode_slice_payload(bad), InvalidInput);
}

}  // namespace
}  // namespace cgview::protocol
