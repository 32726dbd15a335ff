// chaos_animate: its frames are chaos_map's positions after 1..K steps, and
// they survive the .frames format.
#include "chaos/chaos_animate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/animation.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosAnimateTest, FramesFollowTheMapAndSurviveTheFramesFormat) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  const Animation a = chaos_animate(m, {.map = {.kind = chaos::MapKind::ikeda}, .frames = 5}).animation;
  ASSERT_EQ(a.frames.size(), 5u);
  EXPECT_EQ(a.base.faces, m.faces);
  chaos::MapParams p;
  const BBox box = bounding_box(m);
  for (int k = 1; k <= 5; ++k) {
    const auto expect = chaos::apply_map(m.positions, p, k).positions;
    for (std::size_t i = 0; i < expect.size(); i += 97)
      ASSERT_NEAR(norm(to_double(a.frames[std::size_t(k - 1)][i]) - expect[i]), 0, 1e-5 * box.diagonal());
  }
  const std::string bytes = encode_frames(a);
  EXPECT_EQ(bytes.size(), 44 + 12 * m.num_faces() + 6 * m.num_vertices() * 6);
  const Animation back = decode_frames(bytes);
  ASSERT_EQ(back.frames.size(), 5u);
  EXPECT_EQ(back.base.faces, m.faces);
  BBox all = box;
  for (const auto& f : a.frames)
    for (const Vec3f& v : f) all.add(to_double(v));
  const Vec3 tol = all.size() / 131070.0 + Vec3{1e-6, 1e-6, 1e-6};
  for (std::size_t i = 0; i < m.num_vertices(); i += 13) {
    const Vec3 d = to_double(back.frames[4][i]) - to_double(a.frames[4][i]);
    for (int k = 0; k < 3; ++k) ASSERT_LE(std::abs(d[k]), tol[k]);
  }
  EXPECT_THROW(decode_frames(bytes.substr(0, bytes.size() - 1)), InvalidInput);
}

}  // namespace
}  // namespace cgview
