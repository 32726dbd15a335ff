// A face graph cut along the Morton curve (sdf/curve_blocks.h), against the
// curve order itself and the whole graph's arcs and their places.
#include "sdf/curve_blocks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "sdf/curve_order.h"
#include "test_support.h"

namespace cgview::sdf {
namespace {

TEST(CurveBlocks, ConsecutiveFacesAlongTheCurveWithTheArcsBetweenThem) {
  const Mesh mesh = test::torus(4, 1, 48, 24);  // 2304 faces
  const Adjacency g = face_neighbors(mesh, edge_topology(mesh));
  const std::size_t n = g.size();
  const CurveBlocks blocks = curve_blocks(mesh, g, 500);
  ASSERT_EQ(blocks.size(), n / 500);
  ASSERT_EQ(blocks.graphs.size(), blocks.size());
  ASSERT_EQ(blocks.arcs.size(), blocks.size());

  std::vector<Vec3> centre(n);
  for (std::size_t f = 0; f < n; ++f) centre[f] = face_centroid(mesh, f);
  const std::vector<std::uint32_t> order = curve_order(centre);
  std::vector<std::vector<std::uint32_t>> want(blocks.size());
  for (std::size_t i = 0; i < n; ++i) want[i * blocks.size() / n].push_back(order[i]);
  for (std::vector<std::uint32_t>& faces : want) std::sort(faces.begin(), faces.end());
  EXPECT_EQ(blocks.faces, want);

  std::vector<std::size_t> block(n), local(n);
  for (std::size_t k = 0; k < blocks.size(); ++k)
    for (std::size_t i = 0; i < blocks.faces[k].size(); ++i)
      block[blocks.faces[k][i]] = k, local[blocks.faces[k][i]] = i;
  std::size_t cut = 0;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const Adjacency& a = blocks.graphs[k];
    ASSERT_EQ(a.size(), blocks.faces[k].size());
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::uint32_t f = blocks.faces[k][i];
      std::vector<std::uint32_t> own, places;
      for (std::uint32_t j = g.offsets[f]; j < g.offsets[f + 1]; ++j)
        if (block[g.items[j]] == k) own.push_back(std::uint32_t(local[g.items[j]])), places.push_back(j);
        else ++cut;
      EXPECT_EQ(std::vector<std::uint32_t>(a.begin(i), a.end(i)), own) << "face " << f;
      EXPECT_EQ(
          std::vector<std::uint32_t>(blocks.arcs[k].begin() + a.offsets[i], blocks.arcs[k].begin() + a.offsets[i + 1]),
          places)
          << "face " << f;
    }
  }
  EXPECT_GT(cut, 0u);  // the blocks meet
}

TEST(CurveBlocks, UnderTwoBlocksOfFacesTheGraphIsWhole) {
  const Mesh mesh = test::torus(4, 1, 48, 24);
  const Adjacency g = face_neighbors(mesh, edge_topology(mesh));
  const CurveBlocks blocks = curve_blocks(mesh, g, g.size() / 2 + 1);
  EXPECT_EQ(blocks.size(), 0u);
  EXPECT_TRUE(blocks.graphs.empty());
  EXPECT_TRUE(blocks.arcs.empty());
}

}  // namespace
}  // namespace cgview::sdf
