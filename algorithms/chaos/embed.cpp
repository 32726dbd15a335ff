#include "chaos/embed.h"

#include <cstring>
#include <numeric>
#include <unordered_map>
#include <vector>

#include "chaos/maps.h"
#include "core/errors.h"

namespace cgview::chaos {

namespace {

constexpr const char* kDomain = "cgview-chaos-embed";

// Draws slots without repeats: a partial Fisher-Yates shuffle of 0..n-1,
// kept in a vector when many slots are drawn and in a map of the displaced
// entries when a few are (reading a header must not cost O(n)).
class SlotPicker {
 public:
  SlotPicker(std::uint32_t n, std::size_t wanted) : n_(n), dense_(wanted > 4096) {
    if (dense_) {
      v_.resize(n);
      std::iota(v_.begin(), v_.end(), 0u);
    }
  }
  std::uint32_t pick(ChaoticStream& s) {
    const std::uint32_t j = i_ + s.below(n_ - i_);
    std::uint32_t out;
    if (dense_) {
      out = v_[j];
      v_[j] = v_[i_];
    } else {
      out = get(j);
      m_[j] = get(i_);
    }
    ++i_;
    return out;
  }

 private:
  std::uint32_t get(std::uint32_t k) const {
    const auto it = m_.find(k);
    return it == m_.end() ? k : it->second;
  }
  std::uint32_t n_, i_ = 0;
  bool dense_;
  std::vector<std::uint32_t> v_;
  std::unordered_map<std::uint32_t, std::uint32_t> m_;
};

std::uint32_t bits_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}
float float_of(std::uint32_t b) {
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

void check_key(const std::string& key) {
  if (key.empty()) throw InvalidInput("parameter 'key': must not be empty");
}

std::uint32_t checksum(const std::string& message) {
  const auto d = sha256(message);
  return std::uint32_t(d[0]) | std::uint32_t(d[1]) << 8 | std::uint32_t(d[2]) << 16 | std::uint32_t(d[3]) << 24;
}

std::size_t slots_for(std::size_t payload_bits, int k) { return (payload_bits + std::size_t(k) - 1) / std::size_t(k); }

float coordinate(const Mesh& m, std::uint32_t slot) { return float(m.positions[slot / 3][int(slot % 3)]); }

// Reads `count` k-bit chunks from the slots the stream picks, as a bit string.
std::vector<std::uint8_t> read_bits(const Mesh& m, ChaoticStream& s, SlotPicker& picker, std::size_t count, int k,
                                    std::size_t total_bits) {
  std::vector<std::uint8_t> bytes((total_bits + 7) / 8, 0);
  std::size_t bit = 0;
  const std::uint32_t mask = (1u << k) - 1;
  for (std::size_t c = 0; c < count; ++c) {
    const std::uint32_t slot = picker.pick(s);
    const std::uint32_t chunk = (bits_of(coordinate(m, slot)) ^ s.next()) & mask;
    for (int b = 0; b < k && bit < total_bits; ++b, ++bit)
      if (chunk >> b & 1u) bytes[bit / 8] |= std::uint8_t(1u << (bit % 8));
  }
  return bytes;
}

}  // namespace

std::size_t embed_capacity_bytes(std::size_t vertices, int bits) {
  const std::size_t total = 3 * vertices * std::size_t(bits);
  return total > std::size_t(kHeaderBits) ? (total - kHeaderBits) / 8 : 0;
}

EmbedResult embed(const Mesh& cover, const std::string& key, const std::string& message, int k) {
  check_key(key);
  if (k < 1 || k > kMaxEmbedBits)
    throw InvalidInput("parameter 'bits': must be 1 to " + std::to_string(kMaxEmbedBits) + ", got " +
                       std::to_string(k));
  const std::size_t n = cover.num_vertices();
  if (n == 0) throw InvalidInput("chaos_embed: the mesh has no vertices");
  if (3 * n > 0xFFFFFFFFull) throw InvalidInput("chaos_embed: more than 2^32 / 3 vertices");
  const std::size_t capacity = embed_capacity_bytes(n, k);
  // capacity is 0 also when not even the header fits: compare bits, not bytes.
  if (kHeaderBits + 8 * message.size() > 3 * n * std::size_t(k))
    throw InvalidInput("parameter 'message': " + std::to_string(message.size()) + " bytes do not fit: this mesh of " +
                       std::to_string(n) + " vertices holds " + std::to_string(capacity) + " bytes at " +
                       std::to_string(k) + " bits per coordinate (3 k bits per vertex, less a 64-bit header)");

  EmbedResult r;
  r.capacity_bytes = capacity;
  r.mesh = cover;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_finite(cover.positions[i]))
      throw InvalidInput("chaos_embed: vertex " + std::to_string(i) + " has a non-finite coordinate");
    r.mesh.positions[i] = round_to_float32(cover.positions[i]);
  }

  std::string payload(8, '\0');
  const std::uint32_t len = std::uint32_t(message.size()), sum = checksum(message);
  for (int b = 0; b < 4; ++b) payload[std::size_t(b)] = char(len >> (8 * b) & 0xFF);
  for (int b = 0; b < 4; ++b) payload[std::size_t(4 + b)] = char(sum >> (8 * b) & 0xFF);
  payload += message;
  const std::size_t total_bits = 8 * payload.size();
  const std::size_t count = slots_for(total_bits, k);

  ChaoticStream s(kDomain, key);
  SlotPicker picker(std::uint32_t(3 * n), count);
  const std::uint32_t mask = (1u << k) - 1;
  std::size_t bit = 0;
  for (std::size_t c = 0; c < count; ++c) {
    std::uint32_t chunk = 0;
    for (int b = 0; b < k && bit < total_bits; ++b, ++bit)
      chunk |= std::uint32_t(std::uint8_t(payload[bit / 8]) >> (bit % 8) & 1u) << b;
    const std::uint32_t slot = picker.pick(s);
    Vec3& p = r.mesh.positions[slot / 3];
    const std::uint32_t old = bits_of(float(p[int(slot % 3)]));
    p[int(slot % 3)] = float_of((old & ~mask) | ((chunk ^ s.next()) & mask));
  }
  r.slots_used = count;
  return r;
}

ExtractResult extract(const Mesh& stego, const std::string& key) {
  check_key(key);
  const std::size_t n = stego.num_vertices();
  if (n == 0 || 3 * n > 0xFFFFFFFFull) throw InvalidInput("chaos_extract: no message found with this key");
  const std::uint32_t slots = std::uint32_t(3 * n);
  for (int k = 1; k <= kMaxEmbedBits; ++k) {
    const std::size_t header_slots = slots_for(kHeaderBits, k);
    if (header_slots > slots) continue;  // a small mesh holds no header at this k
    ChaoticStream s(kDomain, key);
    SlotPicker picker(slots, header_slots);
    const std::vector<std::uint8_t> h = read_bits(stego, s, picker, header_slots, k, kHeaderBits);
    std::uint32_t len = 0, sum = 0;
    for (int b = 0; b < 4; ++b) len |= std::uint32_t(h[std::size_t(b)]) << (8 * b);
    for (int b = 0; b < 4; ++b) sum |= std::uint32_t(h[std::size_t(4 + b)]) << (8 * b);
    if (len > embed_capacity_bytes(n, k)) continue;
    // Read again from the start: the header's chunks may share a slot with
    // the message's first bits.
    const std::size_t total_bits = kHeaderBits + 8 * std::size_t(len);
    ChaoticStream s2(kDomain, key);
    SlotPicker picker2(slots, slots_for(total_bits, k));
    const std::vector<std::uint8_t> all = read_bits(stego, s2, picker2, slots_for(total_bits, k), k, total_bits);
    std::string message(all.begin() + 8, all.end());
    if (checksum(message) != sum) continue;
    return {std::move(message), k};
  }
  throw InvalidInput("chaos_extract: no message found with this key");
}

}  // namespace cgview::chaos
