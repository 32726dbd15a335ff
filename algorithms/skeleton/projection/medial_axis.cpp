#include "skeleton/projection/medial_axis.h"

#include <algorithm>

namespace cgview::skeleton {

std::vector<std::uint16_t> chamfer_34(const std::vector<std::uint8_t>& mask, int w, int h) {
  constexpr std::uint16_t far = 60000;
  // On a copy with one pixel of outside around it, so that no neighbour
  // needs a bounds check.
  const int pw = w + 2;
  std::vector<std::uint16_t> d(std::size_t(pw) * (h + 2), 0);
  for (int y = 0; y < h; ++y) {
    const std::uint8_t* m = &mask[std::size_t(y) * w];
    std::uint16_t* row = &d[std::size_t(y + 1) * pw + 1];
    for (int x = 0; x < w; ++x) row[x] = m[x] ? far : 0;
  }
  for (int y = 1; y <= h; ++y) {
    std::uint16_t* r = &d[std::size_t(y) * pw];
    const std::uint16_t* up = r - pw;
    for (int x = 1; x <= w; ++x)
      if (r[x]) r[x] = std::uint16_t(std::min({int(r[x]), r[x - 1] + 3, up[x] + 3, up[x - 1] + 4, up[x + 1] + 4}));
  }
  for (int y = h; y >= 1; --y) {
    std::uint16_t* r = &d[std::size_t(y) * pw];
    const std::uint16_t* down = r + pw;
    for (int x = w; x >= 1; --x)
      if (r[x])
        r[x] = std::uint16_t(std::min({int(r[x]), r[x + 1] + 3, down[x] + 3, down[x + 1] + 4, down[x - 1] + 4}));
  }
  std::vector<std::uint16_t> out(std::size_t(w) * h);
  for (int y = 0; y < h; ++y) std::copy_n(&d[std::size_t(y + 1) * pw + 1], w, &out[std::size_t(y) * w]);
  return out;
}

std::vector<std::uint8_t> medial_axis(const std::vector<std::uint16_t>& dt, int w, int h, int min_radius) {
  std::vector<std::uint8_t> axis(dt.size(), 0);
  const int least = std::max(1, 3 * min_radius);
  const auto at = [&](int x, int y) -> int {
    return x < 0 || y < 0 || x >= w || y >= h ? 0 : dt[std::size_t(y) * w + x];
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int v = dt[std::size_t(y) * w + x];
      if (v < least) continue;
      // A neighbour off the image is outside (0), never a bigger disc.
      axis[std::size_t(y) * w + x] = at(x - 1, y) < v + 3 && at(x + 1, y) < v + 3 && at(x, y - 1) < v + 3 &&
                                     at(x, y + 1) < v + 3 && at(x - 1, y - 1) < v + 4 && at(x + 1, y - 1) < v + 4 &&
                                     at(x - 1, y + 1) < v + 4 && at(x + 1, y + 1) < v + 4;
    }
  return axis;
}

}  // namespace cgview::skeleton
