// The binary WebSocket frame (protocol/frames.h) against the committed sample
// frames in tests/data/frames, which the web client's test decodes too: the
// header layout, chunk reassembly, and refusal of malformed frames.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/errors.h"
#include "frames.h"

namespace cgview::protocol {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kFrames = CGVIEW_FRAMES_DIR;

std::string read_bytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  EXPECT_TRUE(f) << "cannot open " << p;
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

struct Sample {
  fs::path bin;
  std::string bytes;
  json sidecar;
};

// cube_0.bin, cube_1.bin, ... with their .json sidecars, in index order.
std::vector<Sample> samples() {
  std::vector<Sample> out;
  for (int i = 0; fs::exists(kFrames / ("cube_" + std::to_string(i) + ".bin")); ++i) {
    const fs::path bin = kFrames / ("cube_" + std::to_string(i) + ".bin");
    fs::path side = bin;
    side.replace_extension(".json");
    out.push_back({bin, read_bytes(bin), json::parse(read_bytes(side))});
  }
  return out;
}

template <class T>
void put_le(std::string& s, std::size_t at, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) s[at + i] = char((std::uint64_t(v) >> (8 * i)) & 0xff);
}

TEST(FramesSamples, EveryCommittedFrameDecodesToItsSidecar) {
  const auto all = samples();
  ASSERT_GE(all.size(), 2u) << "expected several sample frames in " << kFrames;
  for (const Sample& s : all) {
    SCOPED_TRACE(s.bin.filename().string());
    std::string_view chunk;
    const FrameHeader h = decode_frame(s.bytes, &chunk);
    EXPECT_EQ(int(h.kind), s.sidecar["kind"].get<int>());
    EXPECT_EQ(h.request_id, s.sidecar["request_id"].get<std::uint32_t>());
    EXPECT_EQ(h.chunk_index, s.sidecar["chunk_index"].get<std::uint32_t>());
    EXPECT_EQ(h.chunk_count, s.sidecar["chunk_count"].get<std::uint32_t>());
    EXPECT_EQ(h.total_bytes, s.sidecar["total_bytes"].get<std::uint64_t>());
    EXPECT_EQ(s.sidecar["header_bytes"].get<std::uint32_t>(), kFrameHeaderBytes);
    EXPECT_EQ(chunk.size(), s.sidecar["chunk_bytes"].get<std::size_t>());
    EXPECT_EQ(s.bytes.size(), kFrameHeaderBytes + chunk.size());
    EXPECT_EQ(s.sidecar["chunk_count"].get<std::size_t>(), all.size());
  }
}

TEST(FramesSamples, ChunksReassembleToThePayloadByteForByte) {
  const auto all = samples();
  ASSERT_FALSE(all.empty());
  const std::string payload = read_bytes(kFrames / all[0].sidecar["payload_file"].get<std::string>());
  ASSERT_FALSE(payload.empty());
  std::vector<std::string> parts(all.size());
  for (const Sample& s : all) {
    std::string_view chunk;
    const FrameHeader h = decode_frame(s.bytes, &chunk);
    ASSERT_LT(h.chunk_index, parts.size());
    parts[h.chunk_index] = std::string(chunk);
    EXPECT_EQ(h.total_bytes, payload.size());
  }
  std::string joined;
  for (const auto& p : parts) joined += p;
  EXPECT_EQ(joined.size(), payload.size());
  EXPECT_TRUE(joined == payload) << "the reassembled chunks differ from " << all[0].sidecar["payload_file"];
  EXPECT_EQ(payload.substr(0, 5), "DRACO");
}

TEST(FramesSamples, EncodeReproducesTheCommittedHeaderBytes) {
  for (const Sample& s : samples()) {
    SCOPED_TRACE(s.bin.filename().string());
    FrameHeader h;
    h.kind = FrameKind(s.sidecar["kind"].get<std::uint16_t>());
    h.request_id = s.sidecar["request_id"];
    h.chunk_index = s.sidecar["chunk_index"];
    h.chunk_count = s.sidecar["chunk_count"];
    h.total_bytes = s.sidecar["total_bytes"];
    const std::string head = encode_frame_header(h);
    ASSERT_EQ(head.size(), kFrameHeaderBytes);
    EXPECT_TRUE(head == s.bytes.substr(0, kFrameHeaderBytes));
  }
}

TEST(FramesSamples, SplitReproducesTheCommittedFrames) {
  const auto all = samples();
  ASSERT_FALSE(all.empty());
  const std::string payload = read_bytes(kFrames / all[0].sidecar["payload_file"].get<std::string>());
  const auto frames =
      split_into_frames(payload, FrameKind::draco_mesh, all[0].sidecar["request_id"].get<std::uint32_t>(),
                        all[0].sidecar["chunk_bytes"].get<std::size_t>());
  ASSERT_EQ(frames.size(), all.size());
  for (std::size_t i = 0; i < frames.size(); ++i) EXPECT_TRUE(frames[i].bytes() == all[i].bytes) << "frame " << i;
}

TEST(FramesHeader, LayoutIsLittleEndianAt32Bytes) {
  const std::string h = encode_frame_header({FrameKind::draco_mesh, 0x01020304u, 5, 6, 0x0102030405060708ull});
  ASSERT_EQ(h.size(), 32u);
  const std::string expected(
      "CGVF\x01\x00\x01\x00\x04\x03\x02\x01\x05\x00\x00\x00\x06\x00\x00\x00\x20\x00\x00\x00"
      "\x08\x07\x06\x05\x04\x03\x02\x01",
      32);
  EXPECT_TRUE(h == expected);
}

// The reassembled payload of split_into_frames' output, checking each header.
std::string reassemble(const std::vector<Frame>& frames, std::uint32_t request_id, std::uint64_t total) {
  std::string out;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    std::string_view chunk;
    const std::string frame = frames[i].bytes();
    const FrameHeader h = decode_frame(frame, &chunk);
    EXPECT_EQ(h.kind, FrameKind::draco_mesh);
    EXPECT_EQ(h.request_id, request_id);
    EXPECT_EQ(h.chunk_index, i);
    EXPECT_EQ(h.chunk_count, frames.size());
    EXPECT_EQ(h.total_bytes, total);
    out.append(chunk);
  }
  return out;
}

std::string pattern_bytes(std::size_t n) {
  std::string s(n, '\0');
  for (std::size_t i = 0; i < n; ++i) s[i] = char((i * 131 + 7) & 0xff);
  return s;
}

TEST(FramesSplit, RoundTripsOverSizes) {
  struct Case {
    std::size_t size, chunk, frames;
  };
  for (const Case c : {Case{1, 1, 1}, Case{10, 3, 4}, Case{12, 3, 4}, Case{13, 3, 5}, Case{100, 1000, 1},
                       Case{4096, 1024, 4}, Case{4097, 1024, 5}, Case{1 << 20, 1 << 16, 16}}) {
    SCOPED_TRACE("size " + std::to_string(c.size) + " chunk " + std::to_string(c.chunk));
    const std::string payload = pattern_bytes(c.size);
    const auto frames = split_into_frames(payload, FrameKind::draco_mesh, 42, c.chunk);
    ASSERT_EQ(frames.size(), c.frames);
    for (const auto& f : frames) EXPECT_LE(f.size(), kFrameHeaderBytes + c.chunk);
    EXPECT_TRUE(reassemble(frames, 42, c.size) == payload);
  }
}

TEST(FramesSplit, ExactMultipleHasNoEmptyTrailingFrame) {
  const std::string payload = pattern_bytes(64);
  const auto frames = split_into_frames(payload, FrameKind::draco_mesh, 1, 16);
  ASSERT_EQ(frames.size(), 4u);
  for (const auto& f : frames) EXPECT_EQ(f.size(), kFrameHeaderBytes + 16);
  EXPECT_TRUE(reassemble(frames, 1, 64) == payload);
}

TEST(FramesSplit, EmptyPayloadIsOneHeaderOnlyFrame) {
  const auto frames = split_into_frames("", FrameKind::draco_mesh, 9, 16);
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].size(), kFrameHeaderBytes);
  std::string_view chunk = "x";
  const std::string frame = frames[0].bytes();
  const FrameHeader h = decode_frame(frame, &chunk);
  EXPECT_EQ(h.chunk_index, 0u);
  EXPECT_EQ(h.chunk_count, 1u);
  EXPECT_EQ(h.total_bytes, 0u);
  EXPECT_TRUE(chunk.empty());
}

TEST(FramesSplit, DefaultChunkIsFourMiB) {
  EXPECT_EQ(kDefaultChunkBytes, std::size_t(4) << 20);
  const std::string payload = pattern_bytes((std::size_t(4) << 20) + 1);
  const auto frames = split_into_frames(payload, FrameKind::draco_mesh, 3);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[1].size(), kFrameHeaderBytes + 1);
}

TEST(FramesSplit, ZeroChunkSizeIsRefused) {
  EXPECT_THROW(split_into_frames("abc", FrameKind::draco_mesh, 1, 0), InvalidInput);
}

// A valid frame of 16 payload bytes out of 48.
std::string good_frame() { return encode_frame_header({FrameKind::draco_mesh, 5, 1, 3, 48}) + pattern_bytes(16); }

TEST(FramesDecode, AcceptsTheGoodFrame) {
  std::string_view chunk;
  const FrameHeader h = decode_frame(good_frame(), &chunk);
  EXPECT_EQ(h, (FrameHeader{FrameKind::draco_mesh, 5, 1, 3, 48}));
  EXPECT_EQ(chunk.size(), 16u);
  EXPECT_NO_THROW(decode_frame(good_frame()));  // without the chunk out-parameter
}

TEST(FramesDecode, ShortFramesThrow) {
  const std::string f = good_frame();
  for (std::size_t n : {0u, 1u, 4u, 31u}) {
    SCOPED_TRACE(n);
    EXPECT_THROW(decode_frame(std::string_view(f).substr(0, n)), InvalidInput);
  }
}

TEST(FramesDecode, BadMagicThrows) {
  for (const char* magic : {"CGVG", "cgvf", "\0\0\0\0", "DRAC"}) {
    std::string f = good_frame();
    std::copy(magic, magic + 4, f.begin());
    EXPECT_THROW(decode_frame(f), InvalidInput) << magic;
  }
}

TEST(FramesDecode, OtherVersionsThrow) {
  for (std::uint16_t v : {0, 2, 0xffff}) {
    std::string f = good_frame();
    put_le<std::uint16_t>(f, 4, v);
    EXPECT_THROW(decode_frame(f), InvalidInput) << "version " << v;
  }
}

TEST(FramesDecode, UnknownKindThrows) {
  for (std::uint16_t kind : {0, 4, 0xffff}) {  // 1 Draco mesh, 2 voxel slice, 3 animation
    std::string f = good_frame();
    put_le<std::uint16_t>(f, 6, kind);
    EXPECT_THROW(decode_frame(f), InvalidInput) << "kind " << kind;
  }
}

TEST(FramesDecode, ChunkIndexAtOrPastCountThrows) {
  for (std::uint32_t index : {3u, 4u, 0xffffffffu}) {
    std::string f = good_frame();
    put_le<std::uint32_t>(f, 12, index);
    EXPECT_THROW(decode_frame(f), InvalidInput) << "index " << index;
  }
}

TEST(FramesDecode, ZeroChunkCountThrows) {
  std::string f = good_frame();
  put_le<std::uint32_t>(f, 12, 0);
  put_le<std::uint32_t>(f, 16, 0);
  EXPECT_THROW(decode_frame(f), InvalidInput);
}

TEST(FramesDecode, MoreBytesThanTheTotalThrows) {
  std::string f = good_frame();
  put_le<std::uint64_t>(f, 24, 15);  // the frame alone carries 16
  EXPECT_THROW(decode_frame(f), InvalidInput);
  put_le<std::uint64_t>(f, 24, 16);
  EXPECT_NO_THROW(decode_frame(f));
}

TEST(FramesDecode, BadHeaderSizeThrows) {
  for (std::uint32_t hb : {0u, 31u, 1000u}) {
    std::string f = good_frame();
    put_le<std::uint32_t>(f, 20, hb);
    EXPECT_THROW(decode_frame(f), InvalidInput) << "header_bytes " << hb;
  }
}

}  // namespace
}  // namespace cgview::protocol
