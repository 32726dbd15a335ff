// Where each point and face of a mesh's Draco stream came from, as sent to
// the viewer (GET /api/v1/meshes/{id}/stored_order): Draco renumbers vertices
// and faces, and a field or a selection is in the stored order.  The wire
// form is zlib (RFC 1950) of little-endian 32-bit words: the number of
// points P, the number of faces F, then P stored vertex indices and F stored
// face indices, each written as its difference from the one before it (the
// first from 0, modulo 2^32): Edgebreaker walks the surface, so neighbours
// in the stream are mostly neighbours in the file and the differences small.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cgview::protocol {

std::string pack_stored_order(std::span<const std::uint32_t> points, std::span<const std::uint32_t> faces);

struct StoredOrder {
  std::vector<std::uint32_t> points, faces;
};
// Throws cgview::Error when the bytes are not a packed order.
StoredOrder unpack_stored_order(std::string_view packed);

}  // namespace cgview::protocol
