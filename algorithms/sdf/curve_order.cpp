#include "sdf/curve_order.h"

#include <algorithm>
#include <utility>

#include "sdf/parallel_blocks.h"

namespace cgview::sdf {
namespace {
constexpr std::size_t kBlock = 1 << 16;  // points a block in the parallel passes
}  // namespace

std::vector<std::uint32_t> curve_order(std::span<const Vec3> centre) {
  const std::size_t n = centre.size();
  Vec3 lo = n == 0 ? Vec3{} : centre[0], hi = lo;
  for (const Vec3& c : centre)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  std::vector<std::uint64_t> key(n);
  parallel_blocks(n, kBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const Vec3& c = centre[f];
      std::uint64_t code = 0;
      std::uint32_t q[3];
      for (int a = 0; a < 3; ++a) q[a] = hi[a] > lo[a] ? std::uint32_t((c[a] - lo[a]) / (hi[a] - lo[a]) * 1023.0) : 0;
      for (int bit = 9; bit >= 0; --bit)
        for (int a = 0; a < 3; ++a) code = (code << 1) | ((q[a] >> bit) & 1);
      key[f] = code << 32 | f;
    }
  });
  // Sorted by code, ten bits a pass from the lowest, each pass stable (so
  // faces of one code keep their order, as a sort of the whole keys).
  std::vector<std::uint64_t> other(key.size());
  std::vector<std::size_t> count(3 << 10, 0);
  for (std::uint64_t k : key)
    for (int pass = 0; pass < 3; ++pass) ++count[std::size_t(pass << 10) + ((k >> (32 + 10 * pass)) & 1023)];
  for (int pass = 0; pass < 3; ++pass) {
    std::size_t* at = count.data() + (pass << 10);
    for (std::size_t d = 0, sum = 0; d < 1024; ++d) sum += std::exchange(at[d], sum);
    for (std::uint64_t k : key) other[at[(k >> (32 + 10 * pass)) & 1023]++] = k;
    key.swap(other);
  }
  std::vector<std::uint32_t> order(n);
  parallel_blocks(key.size(), kBlock, thread_count(), nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) order[i] = std::uint32_t(key[i]);
  });
  return order;
}

}  // namespace cgview::sdf
