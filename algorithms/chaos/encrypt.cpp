#include "chaos/encrypt.h"

#include <algorithm>
#include <cstring>

#include "chaos/maps.h"
#include "core/errors.h"

namespace cgview::chaos {

namespace {

constexpr const char* kDomain = "cgview-chaos-encrypt";
using F3 = std::array<float, 3>;

// The rank of a float32 in the total order of bit patterns (-0 just below
// +0, NaNs at the ends): an increasing bijection between bit patterns and
// uint32, so that the floats of [lo, hi] are the ranks [rank(lo), rank(hi)].
std::uint32_t rank_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return (b & 0x80000000u) ? ~b : (b | 0x80000000u);
}
float float_of(std::uint32_t r) {
  const std::uint32_t b = (r & 0x80000000u) ? (r & 0x7FFFFFFFu) : ~r;
  float f;
  std::memcpy(&f, &b, 4);
  return f;
}

void check_key(const std::string& key) {
  if (key.empty()) throw InvalidInput("parameter 'key': must not be empty");
}

// The permutations, in the order both directions draw them from the stream.
struct Schedule {
  std::vector<std::uint32_t> V, Qy, Qz, J;  // J: the non-header slots, increasing
  Schedule(ChaoticStream& s, std::uint32_t n) {
    V = s.permutation(n + 2);
    Qy = s.permutation(n);
    Qz = s.permutation(n);
    J.reserve(n);
    for (std::uint32_t j = 0; j < n + 2; ++j)
      if (V[j] < n) J.push_back(j);
  }
  // The plain vertex whose coordinate a goes to the k-th non-header slot.
  std::uint32_t source(std::uint32_t k, int a) const { return V[J[a == 0 ? k : a == 1 ? Qy[k] : Qz[k]]]; }
};

Mesh positions_mesh(const std::vector<F3>& p, std::vector<Tri> faces) {
  Mesh m;
  m.positions.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) m.positions[i] = {p[i][0], p[i][1], p[i][2]};
  m.faces = std::move(faces);
  return m;
}

}  // namespace

Mesh float32_copy(const Mesh& m) {
  Mesh out;
  out.positions.resize(m.positions.size());
  for (std::size_t i = 0; i < m.positions.size(); ++i) out.positions[i] = round_to_float32(m.positions[i]);
  out.faces = m.faces;
  return out;
}

Mesh encrypt(const Mesh& plain, const std::string& key) {
  check_key(key);
  if (plain.num_vertices() == 0) throw InvalidInput("chaos_encrypt: the mesh has no vertices");
  if (plain.num_vertices() > 0xFFFFFFFDull) throw InvalidInput("chaos_encrypt: more than 2^32 - 3 vertices");
  const std::uint32_t n = std::uint32_t(plain.num_vertices());
  for (const Tri& t : plain.faces)
    for (Index i : t)
      if (i >= n)
        throw InvalidInput("chaos_encrypt: a face refers to vertex " + std::to_string(i) + " but there are " +
                           std::to_string(n) + " vertices");
  std::vector<F3> pf(n);
  F3 lo{}, hi{};
  for (std::uint32_t i = 0; i < n; ++i) {
    const Vec3& p = plain.positions[i];
    if (!is_finite(p))
      throw InvalidInput("chaos_encrypt: vertex " + std::to_string(i) + " has a non-finite coordinate");
    pf[i] = {float(p.x), float(p.y), float(p.z)};
    for (int a = 0; a < 3; ++a) {
      if (i == 0 || rank_of(pf[i][a]) < rank_of(lo[a])) lo[a] = pf[i][a];
      if (i == 0 || rank_of(pf[i][a]) > rank_of(hi[a])) hi[a] = pf[i][a];
    }
  }

  ChaoticStream s(kDomain, key);
  const Schedule sch(s, n);
  std::vector<F3> cf(std::size_t(n) + 2);
  std::vector<std::uint32_t> slot_of(std::size_t(n) + 2);  // inverse of V
  for (std::uint32_t j = 0; j < n + 2; ++j) {
    slot_of[sch.V[j]] = j;
    if (sch.V[j] == n) cf[j] = lo;
    if (sch.V[j] == n + 1) cf[j] = hi;
  }
  std::uint64_t base[3], range[3], prev[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    base[a] = rank_of(lo[a]);
    range[a] = std::uint64_t(rank_of(hi[a])) - base[a] + 1;
  }
  for (std::uint32_t k = 0; k < n; ++k)
    for (int a = 0; a < 3; ++a) {
      const std::uint64_t r = rank_of(pf[sch.source(k, a)][a]) - base[a];
      const std::uint64_t c = (r + s.next() + prev[a]) % range[a];
      prev[a] = c;
      cf[sch.J[k]][a] = float_of(std::uint32_t(base[a] + c));
    }

  const std::size_t nf = plain.num_faces();
  if (nf > 0xFFFFFFFFull) throw InvalidInput("chaos_encrypt: more than 2^32 - 1 faces");
  const std::vector<std::uint32_t> F = s.permutation(std::uint32_t(nf));
  std::vector<Tri> faces(nf);
  for (std::size_t j = 0; j < nf; ++j) {
    const Tri& t = plain.faces[F[j]];
    const std::uint32_t r = s.below(3);
    for (int i = 0; i < 3; ++i) faces[j][std::size_t(i)] = slot_of[t[std::size_t((r + i) % 3)]];
  }
  return positions_mesh(cf, std::move(faces));
}

Mesh decrypt(const Mesh& cipher, const std::string& key) {
  check_key(key);
  if (cipher.num_vertices() < 2)
    throw InvalidInput("chaos_decrypt: an encrypted mesh has at least 2 vertices (its header), this one has " +
                       std::to_string(cipher.num_vertices()));
  if (cipher.num_vertices() > 0xFFFFFFFFull) throw InvalidInput("chaos_decrypt: more than 2^32 - 1 vertices");
  const std::uint32_t m = std::uint32_t(cipher.num_vertices()), n = m - 2;
  for (const Tri& t : cipher.faces)
    for (Index i : t)
      if (i >= m)
        throw InvalidInput("chaos_decrypt: a face refers to vertex " + std::to_string(i) + " but there are " +
                           std::to_string(m) + " vertices");
  std::vector<F3> cf(m);
  for (std::uint32_t i = 0; i < m; ++i) {
    const Vec3& p = cipher.positions[i];
    cf[i] = {float(p.x), float(p.y), float(p.z)};
  }

  ChaoticStream s(kDomain, key);
  const Schedule sch(s, n);
  F3 lo{}, hi{};
  for (std::uint32_t j = 0; j < m; ++j) {
    if (sch.V[j] == n) lo = cf[j];
    if (sch.V[j] == n + 1) hi = cf[j];
  }
  // With a wrong key lo and hi are two arbitrary vertices: order them, and
  // clamp ranks into the range, so that the result is garbage but finite.
  std::uint64_t base[3], top[3], range[3], prev[3] = {0, 0, 0};
  for (int a = 0; a < 3; ++a) {
    base[a] = std::min(rank_of(lo[a]), rank_of(hi[a]));
    top[a] = std::max(rank_of(lo[a]), rank_of(hi[a]));
    range[a] = top[a] - base[a] + 1;
  }
  std::vector<F3> pf(n);
  for (std::uint32_t k = 0; k < n; ++k)
    for (int a = 0; a < 3; ++a) {
      const std::uint64_t c = std::clamp<std::uint64_t>(rank_of(cf[sch.J[k]][a]), base[a], top[a]) - base[a];
      const std::uint64_t ks = s.next() % range[a];
      const std::uint64_t r = (c + 2 * range[a] - ks - prev[a]) % range[a];
      prev[a] = c;
      pf[sch.source(k, a)][a] = float_of(std::uint32_t(base[a] + r));
    }

  const std::size_t nf = cipher.num_faces();
  const std::vector<std::uint32_t> F = s.permutation(std::uint32_t(nf));
  std::vector<Tri> faces(nf);
  for (std::size_t j = 0; j < nf; ++j) {
    const Tri& c = cipher.faces[j];
    const std::uint32_t r = s.below(3);
    Tri& t = faces[F[j]];
    for (int i = 0; i < 3; ++i) {
      const std::uint32_t v = sch.V[c[std::size_t(i)]];
      t[std::size_t((r + i) % 3)] = v < n ? v : (n ? v % n : 0);
    }
  }
  if (n == 0) faces.clear();
  return positions_mesh(pf, std::move(faces));
}

}  // namespace cgview::chaos
