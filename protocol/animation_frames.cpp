#include "animation_frames.h"

#include <zlib.h>

#include <cstdint>
#include <cstring>

#include "core/errors.h"

namespace cgview::protocol {
namespace {

std::uint32_t u32_at(std::string_view b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, 4);
  return v;  // little-endian hosts only, as the rest of the wire code
}

// Where the frames start, and how many uint16 values one frame holds; checks the sizes.
std::pair<std::size_t, std::size_t> layout(std::string_view b) {
  if (b.size() < 44 || b.substr(0, 4) != "CGVF") throw InvalidInput("not a .frames file");
  const std::uint64_t n = u32_at(b, 8), f = u32_at(b, 12), m = u32_at(b, 16);
  const std::uint64_t start = 44 + 12 * f, per = 3 * n;
  if (start + 2 * per * m != b.size()) throw InvalidInput("the .frames sizes do not add up to its length");
  return {std::size_t(start), std::size_t(per)};
}

}  // namespace

std::string encode_animation_payload(std::string_view frames_bytes) {
  const auto [start, per] = layout(frames_bytes);
  std::string raw(frames_bytes);
  const std::size_t m = (raw.size() - start) / 2 / (per ? per : 1);
  // Last frame first, so each difference uses the original frame before it.
  for (std::size_t k = m; k-- > 1;) {
    auto* cur = reinterpret_cast<unsigned char*>(raw.data() + start + 2 * per * k);
    const auto* prev = reinterpret_cast<const unsigned char*>(frames_bytes.data() + start + 2 * per * (k - 1));
    const auto* orig = reinterpret_cast<const unsigned char*>(frames_bytes.data() + start + 2 * per * k);
    for (std::size_t i = 0; i < per; ++i) {
      std::uint16_t a, b;
      std::memcpy(&a, orig + 2 * i, 2);
      std::memcpy(&b, prev + 2 * i, 2);
      const std::uint16_t d = std::uint16_t(a - b);
      std::memcpy(cur + 2 * i, &d, 2);
    }
  }
  uLongf packed = compressBound(uLong(raw.size()));
  std::string out(packed, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &packed, reinterpret_cast<const Bytef*>(raw.data()),
                uLong(raw.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw Error("zlib could not compress an animation");
  out.resize(packed);
  return out;
}

std::string decode_animation_payload(std::string_view payload, std::size_t raw_bytes) {
  std::string raw(raw_bytes, '\0');
  uLongf got = uLongf(raw_bytes);
  if (uncompress(reinterpret_cast<Bytef*>(raw.data()), &got, reinterpret_cast<const Bytef*>(payload.data()),
                 uLong(payload.size())) != Z_OK ||
      got != raw_bytes)
    throw InvalidInput("the animation's zlib data is corrupt or not " + std::to_string(raw_bytes) + " bytes");
  const auto [start, per] = layout(raw);
  const std::size_t m = (raw.size() - start) / 2 / (per ? per : 1);
  for (std::size_t k = 1; k < m; ++k) {
    auto* cur = reinterpret_cast<unsigned char*>(raw.data() + start + 2 * per * k);
    const auto* prev = reinterpret_cast<const unsigned char*>(raw.data() + start + 2 * per * (k - 1));
    for (std::size_t i = 0; i < per; ++i) {
      std::uint16_t d, b;
      std::memcpy(&d, cur + 2 * i, 2);
      std::memcpy(&b, prev + 2 * i, 2);
      const std::uint16_t a = std::uint16_t(d + b);
      std::memcpy(cur + 2 * i, &a, 2);
    }
  }
  return raw;
}

}  // namespace cgview::protocol
