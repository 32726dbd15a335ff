#include "stored_order.h"

#include <zlib.h>

#include <cstring>

#include "core/errors.h"

namespace cgview::protocol {

namespace {
// Little-endian words (every frame here assumes a little-endian host).
void put(std::string& out, std::uint32_t w) { out.append(reinterpret_cast<const char*>(&w), 4); }
void put_differences(std::string& out, std::span<const std::uint32_t> values) {
  std::uint32_t previous = 0;
  for (const std::uint32_t v : values) {
    put(out, v - previous);
    previous = v;
  }
}
}  // namespace

std::string pack_stored_order(std::span<const std::uint32_t> points, std::span<const std::uint32_t> faces) {
  std::string raw;
  raw.reserve(4 * (2 + points.size() + faces.size()));
  put(raw, std::uint32_t(points.size()));
  put(raw, std::uint32_t(faces.size()));
  put_differences(raw, points);
  put_differences(raw, faces);
  uLongf packed = compressBound(uLong(raw.size()));
  std::string out(packed, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &packed, reinterpret_cast<const Bytef*>(raw.data()),
                uLong(raw.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw Error("zlib could not compress a stored order");
  out.resize(packed);
  return out;
}

StoredOrder unpack_stored_order(std::string_view packed) {
  z_stream z{};
  if (inflateInit(&z) != Z_OK) throw Error("zlib could not start");
  std::string raw;
  char buf[1 << 16];
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(packed.data()));
  z.avail_in = uInt(packed.size());
  int r = Z_OK;
  while (r == Z_OK) {
    z.next_out = reinterpret_cast<Bytef*>(buf);
    z.avail_out = sizeof buf;
    r = inflate(&z, Z_NO_FLUSH);
    raw.append(buf, sizeof buf - z.avail_out);
  }
  inflateEnd(&z);
  if (r != Z_STREAM_END || raw.size() < 8) throw Error("the stored order is not zlib data of its words");
  std::uint32_t points, faces;
  std::memcpy(&points, raw.data(), 4);
  std::memcpy(&faces, raw.data() + 4, 4);
  if (raw.size() != 4 * (2 + std::uint64_t(points) + faces))
    throw Error("the stored order has " + std::to_string(raw.size()) + " bytes, not 8 and 4 for each of " +
                std::to_string(points) + " points and " + std::to_string(faces) + " faces");
  StoredOrder out;
  auto read = [&](std::vector<std::uint32_t>& into, std::size_t n, std::size_t at) {
    into.resize(n);
    std::uint32_t previous = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::uint32_t d;
      std::memcpy(&d, raw.data() + at + 4 * i, 4);
      into[i] = previous += d;
    }
  };
  read(out.points, points, 8);
  read(out.faces, faces, 8 + 4 * std::size_t(points));
  return out;
}

}  // namespace cgview::protocol
