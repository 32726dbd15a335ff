#include "face_order.h"

#include <zlib.h>

#include <cstring>

#include "core/errors.h"

namespace cgview::protocol {

std::string pack_face_order(std::span<const std::uint32_t> order) {
  std::string raw(order.size() * 4, '\0');
  std::uint32_t previous = 0;
  for (std::size_t f = 0; f < order.size(); ++f) {
    const std::uint32_t d = order[f] - previous;  // an int32 difference, modulo 2^32
    std::memcpy(raw.data() + 4 * f, &d, 4);       // little-endian hosts (as every frame here)
    previous = order[f];
  }
  uLongf packed = compressBound(uLong(raw.size()));
  std::string out(packed, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &packed, reinterpret_cast<const Bytef*>(raw.data()),
                uLong(raw.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw Error("zlib could not compress a face order");
  out.resize(packed);
  return out;
}

std::vector<std::uint32_t> unpack_face_order(std::string_view packed, std::size_t faces) {
  std::string raw(faces * 4, '\0');
  uLongf got = uLongf(raw.size());
  if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &got, reinterpret_cast<const Bytef*>(packed.data()),
                 uLong(packed.size())) != Z_OK ||
      got != raw.size())
    throw Error("the face order is not " + std::to_string(faces) + " packed faces");
  std::vector<std::uint32_t> order(faces);
  std::uint32_t previous = 0;
  for (std::size_t f = 0; f < faces; ++f) {
    std::uint32_t d;
    std::memcpy(&d, raw.data() + 4 * f, 4);
    previous += d;
    order[f] = previous;
  }
  return order;
}

}  // namespace cgview::protocol
