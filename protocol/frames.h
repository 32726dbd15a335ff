// Binary WebSocket frames: a 32-byte little-endian header, then a chunk of
// the payload.  A payload larger than one message is split into chunks that
// the client reassembles by chunk_index.  Layout (see API.md):
//
//   0  "CGVF"        4  u16 version    6  u16 kind      8  u32 request_id
//   12 u32 chunk_index                 16 u32 chunk_count
//   20 u32 header_bytes (32)           24 u64 total payload bytes
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace cgview::protocol {

constexpr std::uint16_t kFrameVersion = 1;
constexpr std::uint32_t kFrameHeaderBytes = 32;
constexpr std::size_t kDefaultChunkBytes = std::size_t(4) << 20;  // under Beast's 16 MiB message limit

enum class FrameKind : std::uint16_t { draco_mesh = 1, voxel_slice = 2, animation = 3 };

struct FrameHeader {
  FrameKind kind = FrameKind::draco_mesh;
  std::uint32_t request_id = 0;
  std::uint32_t chunk_index = 0;
  std::uint32_t chunk_count = 1;
  std::uint64_t total_bytes = 0;
  friend bool operator==(const FrameHeader&, const FrameHeader&) = default;
};

// The 32 header bytes.
std::string encode_frame_header(const FrameHeader& h);
// Parses and checks a frame's header; throws InvalidInput (bad magic,
// version, sizes, an index past the count).  `chunk` gets the payload part.
FrameHeader decode_frame(std::string_view frame, std::string_view* chunk = nullptr);

// One frame of a payload: its header, and a view of its part of the payload
// (the payload is never copied: a server queues the view behind the header).
struct Frame {
  std::string header;
  std::string_view chunk;
  std::size_t size() const { return header.size() + chunk.size(); }
  std::string bytes() const { return header + std::string(chunk); }
};

// All the frames of one payload, each header + at most chunk_bytes of it; an
// empty payload is one frame with no chunk.  The frames view `payload`.
std::vector<Frame> split_into_frames(std::string_view payload, FrameKind kind, std::uint32_t request_id,
                                     std::size_t chunk_bytes = kDefaultChunkBytes);

}  // namespace cgview::protocol
