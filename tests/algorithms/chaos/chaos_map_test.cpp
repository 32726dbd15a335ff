// chaos_map: every map keeps the positions finite and moves them; the map
// parameters' ranges come from their one description (chaos/chaos_params.h).
#include "chaos/chaos_map.h"

#include <gtest/gtest.h>

#include <string>

#include "algorithm_support.h"
#include "chaos_samples.h"
#include "invalid_input.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(ChaosMapTest, EveryMapKeepsPositionsFinite) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  for (chaos::MapKind map : {chaos::MapKind::ikeda, chaos::MapKind::cat, chaos::MapKind::logistic,
                             chaos::MapKind::henon, chaos::MapKind::composite}) {
    const Mesh out = chaos_map(m, {.map = {.kind = map}, .steps = 20}).mesh;
    ASSERT_EQ(out.num_vertices(), m.num_vertices()) << to_string(map);
    for (const Vec3& v : out.positions) ASSERT_TRUE(is_finite(v)) << to_string(map);
    EXPECT_FALSE(test::bit_equal(out.positions, m.positions)) << to_string(map);
  }
}

// A map's name is a choice: the registry refuses one it does not know.
TEST(ChaosMapTest, UnknownMapIsRefusedThroughTheRegistry) {
  const Mesh m = read_mesh(test::sample("bunny00.off"));
  EXPECT_THROW(test::run_algorithm("chaos_map", m, {{"map", std::string("tent")}}), InvalidInput);
}

TEST(ChaosMapTest, RangesComeFromTheDescription) {
  const Mesh m = test::box();
  EXPECT_NE(test::invalid_input_message([&] {
              chaos_map(m, {.map = {.kind = chaos::MapKind::cat, .grid = 1}});
            }).find("parameter 'grid': 1 is under the minimum 2"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([&] {
              chaos_map(m, {.steps = 1001});
            }).find("parameter 'steps': 1001 is over the maximum 1000"),
            std::string::npos);
  EXPECT_NE(test::invalid_input_message([] { chaos_map(Mesh{}); }).find("no vertices"), std::string::npos);
}

TEST(ChaosMapTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(chaos_map(test::box(), {.steps = 3}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
