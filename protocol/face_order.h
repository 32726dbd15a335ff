// The stored face of each face of a mesh's Draco stream, as sent to the
// viewer (GET /api/v1/meshes/{id}/face_order): Draco renumbers faces, and a
// field or a selection is in the stored order.  The wire form is zlib
// (RFC 1950) of one little-endian int32 a face, each the difference from the
// previous face's stored index (the first from 0): Edgebreaker walks the
// surface, so neighbours in the stream are mostly neighbours in the file and
// the differences small.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cgview::protocol {

std::string pack_face_order(std::span<const std::uint32_t> order);
// Throws cgview::Error when the bytes are not a packed order of `faces` faces.
std::vector<std::uint32_t> unpack_face_order(std::string_view packed, std::size_t faces);

}  // namespace cgview::protocol
