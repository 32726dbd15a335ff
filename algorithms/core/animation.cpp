#include "core/animation.h"

#include <cmath>
#include <cstring>

#include "core/errors.h"

namespace cgview {

namespace {

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only, as every reader here
  s.append(b, sizeof(T));
}

template <class T>
T get(std::string_view s, std::size_t& at) {
  if (at + sizeof(T) > s.size()) throw InvalidInput("frames: truncated at byte " + std::to_string(at));
  T v;
  std::memcpy(&v, s.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

}  // namespace

std::string encode_frames(const Animation& a) {
  const std::size_t n = a.base.num_vertices();
  for (const auto& f : a.frames)
    if (f.size() != n)
      throw InvalidInput("frames: a frame has " + std::to_string(f.size()) + " positions for " + std::to_string(n) +
                         " vertices");
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  bool first = true;
  auto add = [&](Vec3f p) {
    for (int k = 0; k < 3; ++k) {
      if (first || p[k] < lo[k]) lo[k] = p[k];
      if (first || p[k] > hi[k]) hi[k] = p[k];
    }
    first = false;
  };
  for (const Vec3& p : a.base.positions) add(to_float(p));
  for (const auto& f : a.frames)
    for (const Vec3f& p : f) add(p);
  std::string s;
  s.reserve(44 + 12 * a.base.num_faces() + 6 * n * a.frame_count());
  s.append("CGVF", 4);
  put<std::uint32_t>(s, 1);
  put<std::uint32_t>(s, std::uint32_t(n));
  put<std::uint32_t>(s, std::uint32_t(a.base.num_faces()));
  put<std::uint32_t>(s, std::uint32_t(a.frame_count()));
  for (float v : lo) put(s, v);
  for (float v : hi) put(s, v);
  for (const Tri& t : a.base.faces)
    for (Index i : t) put<std::uint32_t>(s, i);
  auto frame = [&](auto get_pos) {
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3f p = get_pos(i);
      for (int k = 0; k < 3; ++k) {
        const double ext = double(hi[k]) - double(lo[k]);
        const double q = ext > 0 ? std::round((double(p[k]) - lo[k]) / ext * 65535.0) : 0.0;
        put<std::uint16_t>(s, std::uint16_t(q < 0 ? 0 : q > 65535 ? 65535 : q));
      }
    }
  };
  frame([&](std::size_t i) { return to_float(a.base.positions[i]); });
  for (const auto& f : a.frames) frame([&](std::size_t i) { return f[i]; });
  return s;
}

Animation decode_frames(std::string_view s) {
  std::size_t at = 0;
  if (s.size() < 4 || s.substr(0, 4) != "CGVF") throw InvalidInput("frames: no CGVF magic");
  at = 4;
  if (get<std::uint32_t>(s, at) != 1) throw InvalidInput("frames: unknown version");
  const std::uint32_t n = get<std::uint32_t>(s, at), f = get<std::uint32_t>(s, at), m = get<std::uint32_t>(s, at);
  float lo[3], hi[3];
  for (float& v : lo) v = get<float>(s, at);
  for (float& v : hi) v = get<float>(s, at);
  if (m == 0) throw InvalidInput("frames: no frame");
  const std::size_t need = 44 + 12 * std::size_t(f) + 6 * std::size_t(n) * m;
  if (s.size() != need)
    throw InvalidInput("frames: " + std::to_string(s.size()) + " bytes where the header needs " + std::to_string(need));
  Animation a;
  a.base.faces.resize(f);
  for (Tri& t : a.base.faces)
    for (Index& i : t) {
      i = get<std::uint32_t>(s, at);
      if (i >= n) throw InvalidInput("frames: a face refers to vertex " + std::to_string(i));
    }
  auto read = [&](std::size_t i) {
    Vec3f p;
    for (int k = 0; k < 3; ++k) p[k] = float(lo[k] + (double(hi[k]) - lo[k]) * get<std::uint16_t>(s, at) / 65535.0);
    (void)i;
    return p;
  };
  a.base.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) a.base.positions[i] = to_double(read(i));
  a.frames.assign(m - 1, std::vector<Vec3f>(n));
  for (auto& fr : a.frames)
    for (std::size_t i = 0; i < n; ++i) fr[i] = read(i);
  return a;
}

}  // namespace cgview
