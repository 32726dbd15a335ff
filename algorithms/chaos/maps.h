// Chaotic maps as pure functions, one step at a time, and the key-driven
// chaotic sequences that encryption (chaos/encrypt.h) and embedding
// (chaos/embed.h) draw from.  Teaching and research code: see docs/CHAOS.md.
//
// The maps (each one step; the caller iterates):
//   Ikeda     (x, y) -> (1 + u (x cos t - y sin t), u (x sin t + y cos t)),
//             t = 0.4 - 6 / (1 + x^2 + y^2)          (Ikeda 1979; u < 1 contracts)
//   cat       (i, j) -> (i + j, i + 2 j) mod N       (Arnold's cat map on an N x N grid;
//             area preserving, invertible, periodic: its period is the Pisano period of N / 2, N > 2)
//   logistic  x -> r x (1 - x)                        (May 1976; chaotic for r near 4)
//   Henon     (x, y) -> (1 - a x^2 + y, b x)          (Henon 1976; a = 1.4, b = 0.3)
//   composite the 3D map: Ikeda on (x, y), then on (y, z), then on (z, x)
//
// On a mesh, the maps act on normalized coordinates: the bounding box is
// scaled uniformly (its longest side to length 1) and translated to
// [0, 1]^3 for cat and logistic, to [-1, 1]^3 (longest side 2) for Ikeda, Henon
// and composite, then mapped back with the inverse transform.  The 2D maps
// act on (x, y) and leave z alone; cat acts on the grid cells of (x, y), so
// positions are snapped to the N x N grid (a map on a lattice is what makes it
// exactly periodic).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"

namespace cgview::chaos {

// ---- one step of each map -------------------------------------------------
struct Point2 {
  double x = 0, y = 0;
};
Point2 ikeda_step(Point2 p, double u);
std::array<std::uint32_t, 2> cat_step(std::array<std::uint32_t, 2> ij, std::uint32_t n);
inline double logistic_step(double x, double r) { return r * x * (1.0 - x); }
Point2 henon_step(Point2 p, double a, double b);
Vec3 composite_step(Vec3 p, double u);

// ---- maps on meshes --------------------------------------------------------
enum class MapKind { ikeda, cat, logistic, henon, composite };
// "ikeda", "cat", ...
const char* to_string(MapKind k);

// The defaults are the algorithms' (chaos_map, chaos_animate: their labels
// and ranges are in chaos/chaos_params.h).
struct MapParams {
  MapKind kind = MapKind::ikeda;
  double u = 0.9;           // Ikeda, composite
  double r = 3.99;          // logistic
  double a = 1.4, b = 0.3;  // Henon
  int grid = 1024;          // cat: N (2 or more)
};

// Normalized coordinates of a point set and back (see the header comment).
struct Normalization {
  Vec3 center{};
  double half = 1;    // half the longest side of the bounding box (1 if degenerate)
  bool unit = false;  // true: [0, 1]^3 (cat, logistic); false: [-1, 1]^3
  Vec3 to_normalized(Vec3 p) const;
  Vec3 from_normalized(Vec3 q) const;
};
Normalization normalization_for(const std::vector<Vec3>& points, MapKind map);

// Applies one step of the map to normalized points, in place.  Points that
// leave every bound (|coordinate| > 1e6, Henon outside its basin) stop
// moving: escaped[i] is set and the point keeps its last finite position.
void map_one_step(std::vector<Vec3>& normalized, const MapParams& p, std::vector<std::uint8_t>& escaped);

// Positions after `steps` steps (0 gives the input, snapped to the grid for
// cat).  after_step(k), when given, is called after step k (for progress and
// cancellation; it may throw).  Throws InvalidInput for a bad parameter
// (grid < 2, steps < 0).
struct MapResult {
  std::vector<Vec3> positions;
  std::size_t escaped = 0;  // points that left every bound and were frozen
};
MapResult apply_map(const std::vector<Vec3>& positions, const MapParams& p, int steps,
                    const std::function<void(int)>& after_step = {});

// ---- float32 rounding --------------------------------------------------------
// x rounded to the nearest float32, as a double.  Not double(float(x)): GCC
// 12.2 at -O2 and -O3 (its SLP vectorizer) folds that pair of conversions
// away when it handles two neighbouring coordinates together, which is wrong
// code (seen on Debian bookworm's g++ 12.2.0); the empty asm keeps the float.
inline double round_to_float32(double x) {
  float f = static_cast<float>(x);
#if defined(__GNUC__) && defined(__x86_64__)
  __asm__("" : "+x"(f));
#elif defined(__GNUC__)
  __asm__("" : "+m"(f));
#endif
  return f;
}
inline Vec3 round_to_float32(Vec3 p) { return {round_to_float32(p.x), round_to_float32(p.y), round_to_float32(p.z)}; }

// ---- key-driven chaotic sequences -----------------------------------------
// SHA-256 of the bytes.
std::array<std::uint8_t, 32> sha256(std::string_view bytes);

// A stream of 32-bit words from two coupled logistic maps whose initial
// conditions and parameters come from SHA-256(domain || key): every bit of
// the key changes every word.  Each word mixes the low mantissa bits of both
// maps' states.  In finite precision a chaotic map falls, sooner or later,
// into a cycle (dynamical degradation); the states are therefore perturbed
// every 1024 iterates from a Weyl counter seeded by the digest.  This is a
// teaching device, not a vetted pseudo-random generator.
class ChaoticStream {
 public:
  ChaoticStream(std::string_view domain, std::string_view key);
  std::uint32_t next();
  // Uniform-ish in [0, n) (multiply-shift; a bias below n / 2^32).  n >= 1.
  std::uint32_t below(std::uint32_t n) { return std::uint32_t((std::uint64_t(next()) * n) >> 32); }
  // A permutation of 0..n-1 by Fisher-Yates driven by this stream.
  std::vector<std::uint32_t> permutation(std::uint32_t n);

 private:
  double x_ = 0.3, y_ = 0.6, rx_ = 3.99, ry_ = 3.99;
  std::uint64_t weyl_ = 0, step_ = 0, seed_ = 0;
  void perturb();
};

// Nominal key space of the streams, in bits: the SHA-256 digest that seeds
// them.  The chaotic state (two doubles in (0, 1), two parameters in
// [3.99, 4), a 64-bit counter seed) holds about 2 (52 + 44) + 64 = 256 bits.
inline constexpr double key_space_bits = 256;

}  // namespace cgview::chaos
