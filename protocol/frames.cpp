#include "frames.h"

#include <algorithm>
#include <cstring>

#include "core/errors.h"

namespace cgview::protocol {

namespace {
template <class T>
void put(std::string& s, std::size_t at, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) s[at + i] = char((std::uint64_t(v) >> (8 * i)) & 0xff);
}
template <class T>
T get(std::string_view s, std::size_t at) {
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v |= std::uint64_t(static_cast<unsigned char>(s[at + i])) << (8 * i);
  return T(v);
}
}  // namespace

std::string encode_frame_header(const FrameHeader& h) {
  std::string s(kFrameHeaderBytes, '\0');
  std::memcpy(s.data(), "CGVF", 4);
  put<std::uint16_t>(s, 4, kFrameVersion);
  put<std::uint16_t>(s, 6, std::uint16_t(h.kind));
  put<std::uint32_t>(s, 8, h.request_id);
  put<std::uint32_t>(s, 12, h.chunk_index);
  put<std::uint32_t>(s, 16, h.chunk_count);
  put<std::uint32_t>(s, 20, kFrameHeaderBytes);
  put<std::uint64_t>(s, 24, h.total_bytes);
  return s;
}

FrameHeader decode_frame(std::string_view f, std::string_view* chunk) {
  if (f.size() < kFrameHeaderBytes)
    throw InvalidInput("a frame of " + std::to_string(f.size()) + " bytes is shorter than its 32-byte header");
  if (f.substr(0, 4) != "CGVF") throw InvalidInput("a frame without the CGVF magic");
  if (get<std::uint16_t>(f, 4) != kFrameVersion)
    throw InvalidInput("frame version " + std::to_string(get<std::uint16_t>(f, 4)) + " is not supported");
  const std::uint32_t header_bytes = get<std::uint32_t>(f, 20);
  if (header_bytes < kFrameHeaderBytes || header_bytes > f.size()) throw InvalidInput("a frame's header size is wrong");
  FrameHeader h;
  h.kind = FrameKind(get<std::uint16_t>(f, 6));
  if (h.kind != FrameKind::draco_mesh && h.kind != FrameKind::voxel_slice && h.kind != FrameKind::animation)
    throw InvalidInput("unknown frame kind " + std::to_string(int(h.kind)));
  h.request_id = get<std::uint32_t>(f, 8);
  h.chunk_index = get<std::uint32_t>(f, 12);
  h.chunk_count = get<std::uint32_t>(f, 16);
  h.total_bytes = get<std::uint64_t>(f, 24);
  if (h.chunk_count == 0 || h.chunk_index >= h.chunk_count)
    throw InvalidInput("frame chunk " + std::to_string(h.chunk_index) + " of " + std::to_string(h.chunk_count));
  if (f.size() - header_bytes > h.total_bytes)
    throw InvalidInput("a frame carries more bytes than its payload's total");
  if (chunk) *chunk = f.substr(header_bytes);
  return h;
}

std::vector<Frame> split_into_frames(std::string_view payload, FrameKind kind, std::uint32_t request_id,
                                     std::size_t chunk_bytes) {
  if (chunk_bytes == 0) throw InvalidInput("chunk size must be positive");
  const std::size_t count = payload.empty() ? 1 : (payload.size() + chunk_bytes - 1) / chunk_bytes;
  std::vector<Frame> out;
  out.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
    out.push_back({encode_frame_header({kind, request_id, std::uint32_t(i), std::uint32_t(count), payload.size()}),
                   payload.substr(std::min(payload.size(), i * chunk_bytes), chunk_bytes)});
  return out;
}

}  // namespace cgview::protocol
