#include "chaos/maps.h"

#include <openssl/sha.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <utility>

#include "core/errors.h"
#include "core/shared_library.h"

namespace cgview::chaos {

Point2 ikeda_step(Point2 p, double u) {
  const double t = 0.4 - 6.0 / (1.0 + p.x * p.x + p.y * p.y);
  const double c = std::cos(t), s = std::sin(t);
  return {1.0 + u * (p.x * c - p.y * s), u * (p.x * s + p.y * c)};
}

std::array<std::uint32_t, 2> cat_step(std::array<std::uint32_t, 2> ij, std::uint32_t n) {
  const std::uint64_t i = ij[0], j = ij[1];
  return {std::uint32_t((i + j) % n), std::uint32_t((i + 2 * j) % n)};
}

Point2 henon_step(Point2 p, double a, double b) { return {1.0 - a * p.x * p.x + p.y, b * p.x}; }

Vec3 composite_step(Vec3 p, double u) {
  Point2 q = ikeda_step({p.x, p.y}, u);
  p.x = q.x, p.y = q.y;
  q = ikeda_step({p.y, p.z}, u);
  p.y = q.x, p.z = q.y;
  q = ikeda_step({p.z, p.x}, u);
  p.z = q.x, p.x = q.y;
  return p;
}

const char* to_string(MapKind k) {
  switch (k) {
    case MapKind::ikeda:
      return "ikeda";
    case MapKind::cat:
      return "cat";
    case MapKind::logistic:
      return "logistic";
    case MapKind::henon:
      return "henon";
    case MapKind::composite:
      return "composite";
  }
  return "?";
}

Vec3 Normalization::to_normalized(Vec3 p) const {
  Vec3 q = (p - center) / half;  // [-1, 1] on the longest side
  if (unit) q = (q + Vec3{1, 1, 1}) * 0.5;
  return q;
}

Vec3 Normalization::from_normalized(Vec3 q) const {
  if (unit) q = q * 2.0 - Vec3{1, 1, 1};
  return q * half + center;
}

Normalization normalization_for(const std::vector<Vec3>& points, MapKind map) {
  BBox box;
  for (const Vec3& p : points) box.add(p);
  Normalization n;
  n.unit = map == MapKind::cat || map == MapKind::logistic;
  if (box.empty()) return n;
  const Vec3 s = box.size();
  n.half = std::max({s.x, s.y, s.z}) / 2;
  if (!(n.half > 0)) n.half = 1;
  // For [0, 1] maps the box's min corner goes to the origin (not its centre
  // to 0.5), so that the shorter sides also start at 0.
  n.center = n.unit ? box.min + Vec3{n.half, n.half, n.half} : box.center();
  return n;
}

namespace {

std::uint32_t cell(double x, std::uint32_t n) {
  const double c = std::floor(x * n);
  return c < 0 ? 0 : c >= double(n) ? n - 1 : std::uint32_t(c);
}

bool escaped_value(const Vec3& p) {
  return !is_finite(p) || std::abs(p.x) > 1e6 || std::abs(p.y) > 1e6 || std::abs(p.z) > 1e6;
}

}  // namespace

void map_one_step(std::vector<Vec3>& pts, const MapParams& p, std::vector<std::uint8_t>& escaped) {
  escaped.resize(pts.size(), 0);
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (escaped[i]) continue;
    Vec3 q = pts[i];
    switch (p.kind) {
      case MapKind::ikeda: {
        const Point2 r = ikeda_step({q.x, q.y}, p.u);
        q.x = r.x, q.y = r.y;
        break;
      }
      case MapKind::cat: {
        const auto ij = cat_step({cell(q.x, p.grid), cell(q.y, p.grid)}, p.grid);
        q.x = (ij[0] + 0.5) / p.grid, q.y = (ij[1] + 0.5) / p.grid;
        break;
      }
      case MapKind::logistic:
        q = {logistic_step(q.x, p.r), logistic_step(q.y, p.r), logistic_step(q.z, p.r)};
        break;
      case MapKind::henon: {
        const Point2 r = henon_step({q.x, q.y}, p.a, p.b);
        q.x = r.x, q.y = r.y;
        break;
      }
      case MapKind::composite:
        q = composite_step(q, p.u);
        break;
    }
    if (escaped_value(q)) escaped[i] = 1;
    else pts[i] = q;
  }
}

MapResult apply_map(const std::vector<Vec3>& positions, const MapParams& p, int steps,
                    const std::function<void(int)>& after_step) {
  if (steps < 0) throw InvalidInput("parameter 'steps': must be 0 or more, got " + std::to_string(steps));
  if (p.kind == MapKind::cat && p.grid < 2)
    throw InvalidInput("parameter 'grid': must be 2 or more, got " + std::to_string(p.grid));
  const Normalization n = normalization_for(positions, p.kind);
  std::vector<Vec3> q(positions.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = n.to_normalized(positions[i]);
  if (p.kind == MapKind::cat)
    for (Vec3& v : q) v.x = (cell(v.x, p.grid) + 0.5) / p.grid, v.y = (cell(v.y, p.grid) + 0.5) / p.grid;
  std::vector<std::uint8_t> escaped;
  for (int s = 0; s < steps; ++s) {
    map_one_step(q, p, escaped);
    if (after_step) after_step(s + 1);
  }
  MapResult r;
  r.positions.resize(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) r.positions[i] = n.from_normalized(q[i]);
  r.escaped = std::size_t(std::count(escaped.begin(), escaped.end(), 1));
  return r;
}

namespace {

// OpenSSL's SHA256, from libcrypto opened on the first call: linked in,
// its eager binding (21,000 relocations, -z now) cost every start of a
// job's worker ~0.9 ms of CPU, for the few jobs that take a key.
using Sha256Fn = decltype(&::SHA256);
Sha256Fn sha256_function() {
  static const std::pair<Sha256Fn, std::string> loaded = [] {
    SharedLibrary lib(CGVIEW_LIBCRYPTO);
    const Sha256Fn f = lib.function<Sha256Fn>("SHA256");
    return std::pair(f, lib.why());
  }();
  if (!loaded.first) throw IoError("SHA-256: cannot load OpenSSL: " + loaded.second);
  return loaded.first;
}

}  // namespace

std::array<std::uint8_t, 32> sha256(std::string_view bytes) {
  std::array<std::uint8_t, 32> d{};
  sha256_function()(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(), d.data());
  return d;
}

namespace {

std::uint64_t word(const std::array<std::uint8_t, 32>& d, int k) {
  std::uint64_t w = 0;
  for (int i = 0; i < 8; ++i) w = (w << 8) | d[std::size_t(8 * k + i)];
  return w;
}

// A double in [lo, lo + width) from the top 52 bits of w.
double from_bits(std::uint64_t w, double lo, double width) { return lo + width * double(w >> 12) * 0x1p-52; }

std::uint64_t bits_of(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, 8);
  return b;
}

}  // namespace

ChaoticStream::ChaoticStream(std::string_view domain, std::string_view key) {
  std::string msg(domain);
  msg.push_back('\0');
  msg.append(key);
  const auto d = sha256(msg);
  const std::uint64_t w0 = word(d, 0), w1 = word(d, 1), w2 = word(d, 2), w3 = word(d, 3);
  // States in (0.05, 0.95) and parameters in [3.99, 4): the logistic map is
  // chaotic there and stays inside (0, 1).  The low 12 bits of w0 and w1,
  // unused by from_bits, tune the parameters together with w2.
  x_ = from_bits(w0, 0.05, 0.9);
  y_ = from_bits(w1, 0.05, 0.9);
  rx_ = from_bits(w2 ^ (w0 << 52), 3.99, 0.0099999);
  ry_ = from_bits((w2 << 26 | w2 >> 38) ^ (w1 << 52), 3.99, 0.0099999);
  seed_ = w3 | 1;
  weyl_ = w3;
  // Discard a transient so that the first words do not echo the seeds.
  for (int i = 0; i < 64; ++i) next();
}

namespace {

// x + d wrapped into (0, 1).  Wrapping, not clamping: a clamp sends every
// state near an end to the same value, and the stream would then repeat.
double wrap01(double x, double d) {
  x += d;
  x -= std::floor(x);
  return x > 0 ? x : 0x1p-30;
}

}  // namespace

void ChaoticStream::perturb() {
  weyl_ += 0x9E3779B97F4A7C15ull ^ seed_;
  // Nudges both states by less than 2^-20, a change the map amplifies within
  // a few dozen iterates; the Weyl counter never repeats within 2^64 calls.
  x_ = wrap01(x_, double(weyl_ >> 44) * 0x1p-40);
  y_ = wrap01(y_, double((weyl_ >> 20) & 0xFFFFF) * 0x1p-40);
}

std::uint32_t ChaoticStream::next() {
  x_ = logistic_step(x_, rx_);
  y_ = logistic_step(y_, ry_);
  // Couple the maps weakly so that neither can settle alone.
  x_ += 1e-9 * (y_ - 0.5);
  if ((++step_ & 1023) == 0) perturb();
  if (!(x_ > 0 && x_ < 1) || !(y_ > 0 && y_ < 1)) perturb();
  const std::uint64_t bx = bits_of(x_), by = bits_of(y_);
  const std::uint32_t a = std::uint32_t(bx ^ (bx >> 29)), b = std::uint32_t(by ^ (by >> 23));
  return a ^ (b << 16 | b >> 16);
}

std::vector<std::uint32_t> ChaoticStream::permutation(std::uint32_t n) {
  std::vector<std::uint32_t> p(n);
  std::iota(p.begin(), p.end(), 0u);
  for (std::uint32_t i = n; i > 1; --i) std::swap(p[i - 1], p[below(i)]);
  return p;
}

}  // namespace cgview::chaos
