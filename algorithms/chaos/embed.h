// Hiding a message in the vertex coordinates of a mesh (LSB steganography on
// the float32 mantissa, positions chosen by a chaotic sequence from a key).
// Teaching and research code, NOT vetted cryptography or robust
// watermarking: any change of the coordinates (a smoothing, a re-save as
// text with fewer digits, a float64 -> float32 conversion of a modified mesh)
// destroys the message.  See docs/CHAOS.md.
//
// Layout.  The 3n coordinates are slots (vertex i, axis a) -> 3 i + a.  A
// ChaoticStream seeded by SHA-256("embed", key) draws, for each slot used,
// its index (a partial Fisher-Yates shuffle of the 3n slots) and a 32-bit
// mask.  The payload is a 64-bit header (message length in bytes, 32 bits
// little-endian; the first 4 bytes of SHA-256(message)) followed by the
// message, as a bit string cut into k-bit chunks; chunk c goes into the low
// k mantissa bits of its slot's float32, XORed with the slot's mask.
//
// Capacity: 3 k bits per vertex, less the 64 header bits.
// Distortion: every coordinate is rounded to float32 first (0 for a mesh
// read from a float32 file), then a used coordinate x moves by less than
// 2^k ulp(x) <= 2^(k - 23) |x| (a zero or denormal x: less than
// 2^(k - 149)), so that every vertex moves by at most
// sqrt(3) 2^(k - 23) max|coordinate| (the exponent and sign are never
// touched: no coordinate becomes infinite or NaN).
// Exactness: the message survives storage that keeps the float32 values and
// the vertex order (PLY; OBJ and OFF as CGView writes them; glTF), not STL
// (re-welded) or Draco (quantized); extract tries k = 1..16 and accepts the first header whose length
// fits and whose checksum matches, so a wrong key fails cleanly (a false
// accept has a probability of about 16 x 2^-32).
#pragma once

#include <string>

#include "core/mesh.h"

namespace cgview::chaos {

inline constexpr int kMaxEmbedBits = 16;
inline constexpr int kHeaderBits = 64;

// Message bytes the mesh can hold at k bits per coordinate (0 if none).
std::size_t embed_capacity_bytes(std::size_t vertices, int bits);

struct EmbedResult {
  Mesh mesh;                   // the input with positions rounded to float32 and modified
  std::size_t slots_used = 0;  // coordinates modified (header included)
  std::size_t capacity_bytes = 0;
};
// Throws InvalidInput: empty key ('key'), bits outside 1..16 ('bits'), a
// message longer than the capacity ('message', with both numbers), a mesh
// with no vertices or a non-finite coordinate.
EmbedResult embed(const Mesh& cover, const std::string& key, const std::string& message, int bits = 4);

struct ExtractResult {
  std::string message;
  int bits = 0;  // k found in the header
};
// Throws InvalidInput "no message found with this key" when no k gives a
// valid header (wrong key, or no message), or for an empty key.
ExtractResult extract(const Mesh& stego, const std::string& key);

}  // namespace cgview::chaos
