// STL, binary and ascii.  A binary file is recognised by its size (84 + 50
// bytes per triangle), whatever its first word; corners with identical
// coordinates are welded into shared vertices (an open-addressing table on
// the exact float bits: STL writers repeat the same floats for a shared corner).
#include <bit>
#include <cstring>

#include "io/readers.h"
#include "io/text_scanner.h"

namespace cgview::detail {

namespace {

// Maps each corner to a vertex, welding equal coordinates when asked.
class Welder {
 public:
  Welder(Mesh& mesh, std::size_t corners, bool weld) : mesh_(mesh), weld_(weld) {
    mesh.positions.reserve(weld ? corners / 4 : corners);
    if (weld) {
      std::size_t cap = 16;
      while (cap < corners) cap <<= 1;  // welded corners are a fraction of all
      table_.assign(cap, UINT32_MAX);
      keys_.reserve(corners / 4);
    }
  }
  Index add(const float p[3]) {
    if (!weld_) return push(p);
    std::array<std::uint32_t, 3> bits;
    std::memcpy(bits.data(), p, 12);
    for (std::uint32_t& b : bits)
      if (b == 0x80000000u) b = 0;  // -0 and +0 are the same corner
    if (keys_.size() * 2 + 2 > table_.size()) grow();
    const std::size_t mask = table_.size() - 1;
    for (std::size_t slot = hash(bits) & mask;; slot = (slot + 1) & mask) {
      const Index v = table_[slot];
      if (v == UINT32_MAX) {
        keys_.push_back(bits);
        return table_[slot] = push(p);
      }
      if (keys_[v] == bits) return v;
    }
  }

 private:
  Index push(const float p[3]) {
    mesh_.positions.push_back({p[0], p[1], p[2]});
    return Index(mesh_.positions.size() - 1);
  }
  static std::uint64_t hash(const std::array<std::uint32_t, 3>& b) {
    std::uint64_t h = (b[0] * 0x9E3779B97F4A7C15ull) ^ (b[1] * 0xC2B2AE3D27D4EB4Full) ^ (b[2] * 0x165667B19E3779F9ull);
    return h ^ (h >> 29);
  }
  void grow() {
    table_.assign(table_.size() * 2, UINT32_MAX);
    const std::size_t mask = table_.size() - 1;
    for (Index v = 0; v < keys_.size(); ++v) {
      std::size_t slot = hash(keys_[v]) & mask;
      while (table_[slot] != UINT32_MAX) slot = (slot + 1) & mask;
      table_[slot] = v;
    }
  }
  Mesh& mesh_;
  bool weld_;
  std::vector<Index> table_;
  std::vector<std::array<std::uint32_t, 3>> keys_;
};

void read_binary(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result) {
  std::uint32_t n;
  std::memcpy(&n, bytes.data() + 80, 4);
  if constexpr (std::endian::native == std::endian::big) n = __builtin_bswap32(n);
  Welder weld(result.mesh, std::size_t(n) * 3, options.weld_stl);
  result.mesh.faces.resize(n);
  const char* p = bytes.data() + 84;
  for (std::uint32_t f = 0; f < n; ++f, p += 50) {
    float c[12];
    std::memcpy(c, p, 48);
    for (int k = 0; k < 3; ++k) {
      const float* q = c + 3 + 3 * k;
      if (!std::isfinite(q[0]) || !std::isfinite(q[1]) || !std::isfinite(q[2]))
        throw ParseError(name, "triangle " + std::to_string(f) + " has a non-finite coordinate", std::nullopt,
                         std::uint64_t(p - bytes.data()) + 12 + 12 * k);
      result.mesh.faces[f][k] = weld.add(q);
    }
  }
}

void read_ascii(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result) {
  TextScanner in(bytes, name);
  in.skip_space(false);
  if (in.word() != "solid") in.fail("not an STL file: it starts neither with 'solid' nor with a binary header");
  in.skip_line();
  // About 250 bytes per facet in ascii.
  Welder weld(result.mesh, std::min<std::size_t>(bytes.size() / 250 + 16, bytes.size()) * 3, options.weld_stl);
  std::vector<Index> loop;
  std::uint64_t polygons = 0;
  bool ended = false;
  while (!in.at_end()) {
    in.skip_space(false);
    if (in.at_end()) break;
    const char* at = in.pos();
    std::string_view w = in.word();
    if (w == "facet" || w == "normal" || w == "outer" || w == "loop" || w == "endfacet") {
      in.skip_line();
    } else if (w == "vertex") {
      float p[3];
      for (float& x : p) x = float(in.need_double("a vertex coordinate"));
      if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
        in.fail_at(at, "a vertex has a non-finite coordinate");
      loop.push_back(weld.add(p));
    } else if (w == "endloop") {
      if (loop.size() < 3)
        in.fail_at(at, "a facet has " + std::to_string(loop.size()) + " vertices (at least 3 needed)");
      if (loop.size() > 3) ++polygons;
      for (std::size_t i = 1; i + 1 < loop.size(); ++i) result.mesh.faces.push_back({loop[0], loop[i], loop[i + 1]});
      loop.clear();
    } else if (w == "endsolid") {
      ended = true;
      in.skip_line();
    } else if (w == "solid" && ended) {  // several solids in one file
      ended = false;
      in.skip_line();
    } else {
      in.fail_at(at, "unexpected " + in.describe_here().substr(0, 0) + "'" + std::string(w.substr(0, 24)) +
                         "' in an ascii STL");
    }
  }
  if (!loop.empty()) in.fail("the file ends inside a facet (truncated?)");
  if (!ended) result.warnings.push_back("the file has no endsolid line (truncated?)");
  if (polygons) result.warnings.push_back(std::to_string(polygons) + " polygons were split into triangles");
}

}  // namespace

void read_stl(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result) {
  if (bytes.empty()) throw ParseError(name, "the file is empty", std::nullopt, std::nullopt);
  if (bytes.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, bytes.data() + 80, 4);
    if constexpr (std::endian::native == std::endian::big) n = __builtin_bswap32(n);
    if (84 + 50 * std::uint64_t(n) == bytes.size()) return read_binary(bytes, name, options, result);
    std::size_t i = 0;
    while (i < bytes.size() && TextScanner::is_space(bytes[i])) ++i;
    if (bytes.substr(i, 5) != "solid")
      throw ParseError(name,
                       "a binary STL header claims " + std::to_string(n) + " triangles (" +
                           std::to_string(84 + 50 * std::uint64_t(n)) + " bytes) but the file has " +
                           std::to_string(bytes.size()) + " bytes",
                       std::nullopt, 80);
  }
  read_ascii(bytes, name, options, result);
}

}  // namespace cgview::detail
