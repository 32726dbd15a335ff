// Mesh: geometry helpers, adjacency, edge topology, attribute splitting,
// subdivision and validation, on generated shapes with known answers.
#include "core/mesh.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <numeric>

#include "core/errors.h"
#include "core/mesh_report.h"
#include "core/threads.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::box;
using test::grid;
using test::torus;
using test::uv_sphere;

constexpr Index kNone = std::numeric_limits<Index>::max();

using test::merged;

double angle_between(Vec3 a, Vec3 b) { return std::atan2(norm(cross(a, b)), dot(a, b)); }

// Vertex id of grid(n) point (i, j).
Index gid(int n, int i, int j) { return Index(j * (n + 1) + i); }

TEST(MeshTest, CountsAndFlags) {
  Mesh m = box();
  EXPECT_EQ(m.num_vertices(), 8u);
  EXPECT_EQ(m.num_faces(), 12u);
  EXPECT_FALSE(m.has_normals());
  EXPECT_FALSE(m.has_uvs());
  EXPECT_FALSE(m.has_colors());
  EXPECT_TRUE(m.attributes_per_vertex());
  m.uvs.assign(3, {});
  m.uv_faces.assign(12, {0, 1, 2});
  EXPECT_TRUE(m.has_uvs());
  EXPECT_FALSE(m.attributes_per_vertex());
}

TEST(MeshTest, BoundingBox) {
  const BBox b = bounding_box(box({-1, 2, 3}, {4, 5, 10}));
  EXPECT_FALSE(b.empty());
  EXPECT_EQ(b.min, (Vec3{-1, 2, 3}));
  EXPECT_EQ(b.max, (Vec3{4, 5, 10}));
  EXPECT_EQ(b.size(), (Vec3{5, 3, 7}));
  EXPECT_EQ(b.center(), (Vec3{1.5, 3.5, 6.5}));
  EXPECT_DOUBLE_EQ(b.diagonal(), std::sqrt(25.0 + 9.0 + 49.0));

  const BBox empty = bounding_box(Mesh{});
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.size(), Vec3{});
  EXPECT_EQ(empty.diagonal(), 0.0);

  const BBox s = bounding_box(uv_sphere(2.0));
  EXPECT_NEAR(s.min.z, -2.0, 1e-12);
  EXPECT_NEAR(s.max.z, 2.0, 1e-12);
  EXPECT_NEAR(s.max.x, 2.0, 1e-12);
}

TEST(MeshTest, FaceAreasOfBoxSumToSurface) {
  const Mesh m = box();
  const auto areas = face_areas(m);
  ASSERT_EQ(areas.size(), 12u);
  for (double a : areas) EXPECT_NEAR(a, 0.5, 1e-15);
  EXPECT_NEAR(std::accumulate(areas.begin(), areas.end(), 0.0), 6.0, 1e-12);

  // Scaled box: faces of 2x3, 2x4 and 3x4.
  const auto big = face_areas(box({0, 0, 0}, {2, 3, 4}));
  EXPECT_NEAR(std::accumulate(big.begin(), big.end(), 0.0), 2 * (6.0 + 8.0 + 12.0), 1e-12);
}

TEST(MeshTest, FaceNormalsOfBoxAreUnitAndOutward) {
  const Mesh m = box({-1, -1, -1}, {3, 1, 2});
  const Vec3 c = bounding_box(m).center();
  const auto normals = face_normals(m);
  ASSERT_EQ(normals.size(), m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const Tri& t = m.faces[f];
    const Vec3 fc = (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
    EXPECT_NEAR(norm(normals[f]), 1.0, 1e-12) << "face " << f;
    EXPECT_GT(dot(normals[f], fc - c), 0.0) << "face " << f << " points inward";
    // Axis-aligned: exactly one nonzero component, of magnitude 1.
    int nonzero = 0;
    for (int k = 0; k < 3; ++k) nonzero += std::abs(normals[f][k]) > 1e-12;
    EXPECT_EQ(nonzero, 1) << "face " << f;
  }
  // The first two faces lie in z = min: normal -z.
  EXPECT_NEAR(normals[0].z, -1.0, 1e-12);
  EXPECT_NEAR(normals[1].z, -1.0, 1e-12);
}

TEST(MeshTest, DegenerateFaceHasZeroNormalAndArea) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  m.faces = {{0, 1, 2}, {0, 0, 1}};
  const auto n = face_normals(m);
  const auto a = face_areas(m);
  EXPECT_EQ(n[0], Vec3{});
  EXPECT_EQ(n[1], Vec3{});
  EXPECT_EQ(a[0], 0.0);
  EXPECT_EQ(a[1], 0.0);
}

TEST(MeshTest, VertexNormalsOfSphereAreRadialForEveryWeighting) {
  const Mesh m = uv_sphere(1.5, 16, 32);
  const double max_angle = 2.0 * std::numbers::pi / 180.0;  // 2 degrees
  for (NormalWeighting w : {NormalWeighting::uniform, NormalWeighting::area, NormalWeighting::angle}) {
    const auto n = vertex_normals(m, w);
    ASSERT_EQ(n.size(), m.num_vertices());
    double worst = 0;
    for (std::size_t v = 0; v < n.size(); ++v) {
      EXPECT_NEAR(norm(n[v]), 1.0, 1e-12) << "vertex " << v;
      worst = std::max(worst, angle_between(n[v], m.positions[v]));
    }
    EXPECT_LT(worst, max_angle) << "weighting " << int(w);
    // The poles are symmetric: exactly along the axis.
    EXPECT_NEAR(n.front().z, 1.0, 1e-12);
    EXPECT_NEAR(n.back().z, -1.0, 1e-12);
  }
}

TEST(MeshTest, VertexNormalWeightingsDiffer) {
  // A corner of a box: three faces meet at vertex 0 with one triangle on x=0
  // ... instead use an L of two triangles of different areas and angles.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 3}, {0, 3, 0}};
  // Face 0 in z = 0 (normal +z), area 0.5, angle at 0: 90 degrees.
  // Face 1 in x = 0 (normal +x), area 4.5, angle at 0: 90 degrees.
  // Face 2 in x = 0 too (normal +x), degenerate-free, small: (0, 2->... )
  m.faces = {{0, 1, 2}, {0, 4, 3}};
  const auto uni = vertex_normals(m, NormalWeighting::uniform);
  const auto area = vertex_normals(m, NormalWeighting::area);
  const auto ang = vertex_normals(m, NormalWeighting::angle);
  const double s = 1 / std::sqrt(2.0);
  EXPECT_NEAR(uni[0].x, s, 1e-12);
  EXPECT_NEAR(uni[0].z, s, 1e-12);
  EXPECT_NEAR(ang[0].x, s, 1e-12);  // equal 90-degree corners
  EXPECT_NEAR(ang[0].z, s, 1e-12);
  // Area weights 0.5 (+z) and 4.5 (+x): direction (4.5, 0, 0.5).
  const Vec3 want = normalized(Vec3{4.5, 0, 0.5});
  EXPECT_NEAR(area[0].x, want.x, 1e-12);
  EXPECT_NEAR(area[0].z, want.z, 1e-12);
  // A vertex of one face only gets that face's normal.
  EXPECT_NEAR(uni[1].z, 1.0, 1e-12);
  EXPECT_NEAR(area[3].x, 1.0, 1e-12);
}

TEST(MeshTest, VertexNormalOfIsolatedVertexIsZero) {
  Mesh m = box();
  m.positions.push_back({5, 5, 5});
  const auto n = vertex_normals(m);
  EXPECT_EQ(n.back(), Vec3{});
}

TEST(MeshTest, VertexFacesOnGrid) {
  const int n = 4;
  const Mesh m = grid(n);
  const Adjacency vf = vertex_faces(m);
  ASSERT_EQ(vf.size(), m.num_vertices());
  EXPECT_EQ(vf.items.size(), 3 * m.num_faces());
  EXPECT_EQ(vf.degree(gid(n, 0, 0)), 2u);  // both triangles of the corner square
  EXPECT_EQ(vf.degree(gid(n, n, 0)), 1u);
  EXPECT_EQ(vf.degree(gid(n, 0, n)), 1u);
  EXPECT_EQ(vf.degree(gid(n, n, n)), 2u);
  EXPECT_EQ(vf.degree(gid(n, 2, 0)), 3u);  // bottom side
  EXPECT_EQ(vf.degree(gid(n, 0, 2)), 3u);  // left side
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) EXPECT_EQ(vf.degree(gid(n, i, j)), 6u) << i << "," << j;
  // Each listed face really uses the vertex, in increasing face order.
  for (std::size_t v = 0; v < vf.size(); ++v) {
    EXPECT_TRUE(std::is_sorted(vf.begin(v), vf.end(v)));
    for (auto f = vf.begin(v); f != vf.end(v); ++f) {
      const Tri& t = m.faces[*f];
      EXPECT_TRUE(t[0] == v || t[1] == v || t[2] == v);
    }
  }
}

TEST(MeshTest, VertexNeighborsOnGridAndBox) {
  const int n = 4;
  const Mesh g = grid(n);
  const Adjacency nb = vertex_neighbors(g);
  ASSERT_EQ(nb.size(), g.num_vertices());
  EXPECT_EQ(nb.degree(gid(n, 0, 0)), 3u);
  EXPECT_EQ(nb.degree(gid(n, n, 0)), 2u);
  EXPECT_EQ(nb.degree(gid(n, 0, n)), 2u);
  EXPECT_EQ(nb.degree(gid(n, n, n)), 3u);
  EXPECT_EQ(nb.degree(gid(n, 1, 0)), 4u);
  for (int j = 1; j < n; ++j)
    for (int i = 1; i < n; ++i) EXPECT_EQ(nb.degree(gid(n, i, j)), 6u);
  // Interior vertex (1,1): left, right, down, up and the two diagonal ones.
  const Index c = gid(n, 1, 1);
  std::vector<std::uint32_t> got(nb.begin(c), nb.end(c));
  std::vector<std::uint32_t> want = {gid(n, 0, 0), gid(n, 1, 0), gid(n, 0, 1),
                                     gid(n, 2, 1), gid(n, 1, 2), gid(n, 2, 2)};
  std::sort(want.begin(), want.end());
  EXPECT_EQ(got, want);

  // Box: the sum of degrees is twice the edge count (18), sorted, no self.
  const Mesh b = box();
  const Adjacency bn = vertex_neighbors(b);
  std::size_t sum = 0;
  for (std::size_t v = 0; v < bn.size(); ++v) {
    sum += bn.degree(v);
    EXPECT_TRUE(std::is_sorted(bn.begin(v), bn.end(v)));
    EXPECT_TRUE(std::adjacent_find(bn.begin(v), bn.end(v)) == bn.end(v));
    EXPECT_TRUE(std::find(bn.begin(v), bn.end(v), v) == bn.end(v));
    EXPECT_GE(bn.degree(v), 3u);
  }
  EXPECT_EQ(sum, 36u);
  EXPECT_EQ(bn.items.size(), 36u);
  // Box vertex 0 (a corner with no diagonal) has 3 neighbours, vertex 1 has 5.
  EXPECT_EQ(std::vector<std::uint32_t>(bn.begin(0), bn.end(0)), (std::vector<std::uint32_t>{1, 2, 4}));
  EXPECT_EQ(bn.degree(1), 5u);
}

TEST(MeshTest, ClosedManifoldHasAsManyFacesAsNeighborsPerVertex) {
  for (const Mesh& m : {box(), torus(), uv_sphere(1.0, 6, 10)}) {
    const Adjacency vf = vertex_faces(m), vn = vertex_neighbors(m);
    for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(vf.degree(v), vn.degree(v)) << "vertex " << v;
  }
  const Adjacency bf = vertex_faces(box());
  EXPECT_EQ(bf.degree(0), 3u);
  EXPECT_EQ(std::vector<std::uint32_t>(bf.begin(0), bf.end(0)), (std::vector<std::uint32_t>{0, 4, 8}));
  EXPECT_EQ(bf.degree(1), 5u);
}

TEST(MeshTest, VertexNeighborsSkipsRepeatedCorner) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 0, 1}, {0, 1, 2}};
  const Adjacency nb = vertex_neighbors(m);
  EXPECT_EQ(std::vector<std::uint32_t>(nb.begin(0), nb.end(0)), (std::vector<std::uint32_t>{1, 2}));
  EXPECT_EQ(std::vector<std::uint32_t>(nb.begin(1), nb.end(1)), (std::vector<std::uint32_t>{0, 2}));
  EXPECT_EQ(std::vector<std::uint32_t>(nb.begin(2), nb.end(2)), (std::vector<std::uint32_t>{0, 1}));
}

TEST(MeshTest, EdgeTopologyOfBox) {
  const Mesh m = box();
  const EdgeTopology topo = edge_topology(m);
  ASSERT_EQ(topo.edges.size(), 18u);
  ASSERT_EQ(topo.edge_faces.size(), 18u);
  ASSERT_EQ(topo.face_edges.size(), 12u);
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    EXPECT_LT(topo.edges[e][0], topo.edges[e][1]);
    EXPECT_EQ(topo.edge_faces.degree(e), 2u) << "edge " << e;
  }
  // No edge is listed twice.
  auto sorted = topo.edges;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_TRUE(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());
  // face_edges[f][k] is the side (v_k, v_k+1) of face f, and lists f back.
  for (std::uint32_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index e = topo.face_edges[f][k];
      ASSERT_LT(e, topo.edges.size());
      const Index a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
      EXPECT_EQ(topo.edges[e][0], std::min(a, b));
      EXPECT_EQ(topo.edges[e][1], std::max(a, b));
      EXPECT_TRUE(std::find(topo.edge_faces.begin(e), topo.edge_faces.end(e), f) != topo.edge_faces.end(e));
    }
}

TEST(MeshTest, EdgeTopologyOfGrid) {
  const int n = 4;
  const Mesh m = grid(n);
  const EdgeTopology topo = edge_topology(m);
  // 2 n (n+1) axis edges and n^2 diagonals.
  EXPECT_EQ(topo.edges.size(), std::size_t(2 * n * (n + 1) + n * n));  // 56
  std::size_t border = 0, inner = 0;
  for (std::size_t e = 0; e < topo.edges.size(); ++e) {
    const auto d = topo.edge_faces.degree(e);
    if (d == 1) ++border;
    else if (d == 2) ++inner;
    else ADD_FAILURE() << "edge " << e << " has " << d << " faces";
  }
  EXPECT_EQ(border, std::size_t(4 * n));  // 16
  EXPECT_EQ(inner, 56u - 16u);
}

TEST(MeshTest, EdgeTopologySkipsCollapsedSides) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {1, 1, 2}};
  const EdgeTopology topo = edge_topology(m);
  EXPECT_EQ(topo.edges.size(), 3u);
  EXPECT_EQ(topo.face_edges[1][0], kNone);                       // side 1-1
  ASSERT_NE(topo.face_edges[1][1], kNone);                       // side 1-2, shared with face 0
  EXPECT_EQ(topo.edge_faces.degree(topo.face_edges[1][1]), 3u);  // face 0 once, face 1 twice
  EXPECT_EQ(topo.face_edges[1][1], topo.face_edges[1][2]);
  EXPECT_EQ(topo.face_edges[1][1], topo.face_edges[0][1]);
}

// Above 64k faces a thread a share of them builds the topology and the
// face graph: the same as a map from each side's two ends to its faces in
// their order, on a grid of 180k faces with its vertices numbered out of
// order, three faces on one edge and a face with a collapsed side.
TEST(MeshTest, EdgeTopologyAndFaceNeighborsOfALargeMeshMatchAMapOfItsSides) {
  Mesh m = grid(300);
  const std::size_t nv = m.positions.size();
  std::vector<Index> rename(nv);
  for (std::size_t v = 0; v < nv; ++v) rename[v] = Index((v * 7919) % nv);  // 7919 is prime to 301^2
  for (Tri& t : m.faces)
    for (Index& i : t) i = rename[i];
  m.faces.push_back({m.faces[5][0], m.faces[5][1], m.faces[9][2]});  // a third face on face 5's first side
  m.faces.push_back({m.faces[7][0], m.faces[7][0], m.faces[7][1]});  // a collapsed side
  ASSERT_GT(m.faces.size(), 2 * kItemsPerThread);
  std::map<std::array<Index, 2>, std::vector<std::uint32_t>> sides;  // (low, high) -> face * 3 + k
  for (std::uint32_t f = 0; f < m.faces.size(); ++f)
    for (std::uint32_t k = 0; k < 3; ++k) {
      const Index a = m.faces[f][k], b = m.faces[f][(k + 1) % 3];
      if (a != b) sides[{std::min(a, b), std::max(a, b)}].push_back(3 * f + k);
    }
  const EdgeTopology topo = edge_topology(m);
  ASSERT_EQ(topo.edges.size(), sides.size());
  ASSERT_EQ(topo.edge_faces.size(), sides.size());
  std::vector<std::array<Index, 3>> face_edges(m.faces.size(), {kNone, kNone, kNone});
  std::size_t e = 0;
  for (const auto& [ends, corners] : sides) {
    ASSERT_EQ(topo.edges[e], ends) << "edge " << e;
    std::vector<std::uint32_t> faces;
    for (std::uint32_t c : corners) faces.push_back(c / 3), face_edges[c / 3][c % 3] = Index(e);
    ASSERT_EQ(std::vector<std::uint32_t>(topo.edge_faces.begin(e), topo.edge_faces.end(e)), faces) << "edge " << e;
    ++e;
  }
  ASSERT_EQ(topo.face_edges, face_edges);
  const Adjacency fn = face_neighbors(m, topo);
  ASSERT_EQ(fn.size(), m.faces.size());
  for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
    std::vector<std::uint32_t> expected;
    for (Index edge : face_edges[f])
      if (edge != kNone)
        for (auto g = topo.edge_faces.begin(edge); g != topo.edge_faces.end(edge); ++g)
          if (*g != f) expected.push_back(*g);
    ASSERT_EQ(std::vector<std::uint32_t>(fn.begin(f), fn.end(f)), expected) << "face " << f;
  }
}

TEST(MeshTest, FaceNeighborsOfClosedMeshAreThree) {
  for (const Mesh& m : {box(), torus(), uv_sphere(1.0, 8, 12)}) {
    const EdgeTopology topo = edge_topology(m);
    const Adjacency fn = face_neighbors(m, topo);
    ASSERT_EQ(fn.size(), m.num_faces());
    for (std::uint32_t f = 0; f < fn.size(); ++f) {
      ASSERT_EQ(fn.degree(f), 3u) << "face " << f;
      for (auto g = fn.begin(f); g != fn.end(f); ++g) {
        EXPECT_NE(*g, f);
        // Symmetric relation.
        EXPECT_TRUE(std::find(fn.begin(*g), fn.end(*g), f) != fn.end(*g));
      }
    }
  }
}

TEST(MeshTest, FaceNeighborsOnGrid) {
  const Mesh m = grid(1);  // two triangles sharing the diagonal
  const Adjacency fn = face_neighbors(m, edge_topology(m));
  ASSERT_EQ(fn.size(), 2u);
  EXPECT_EQ(std::vector<std::uint32_t>(fn.begin(0), fn.end(0)), std::vector<std::uint32_t>{1});
  EXPECT_EQ(std::vector<std::uint32_t>(fn.begin(1), fn.end(1)), std::vector<std::uint32_t>{0});
  const Mesh g = grid(4);
  const Adjacency gn = face_neighbors(g, edge_topology(g));
  std::size_t total = 0;
  for (std::size_t f = 0; f < gn.size(); ++f) total += gn.degree(f);
  EXPECT_EQ(total, 2u * 40u);  // twice the interior edges
}

TEST(MeshTest, FaceNeighborsWithCollapsedSide) {
  // Face 0 has a collapsed side; its other two sides are both the edge 1-2,
  // which face 1 shares.  Every listed neighbour must be a real one.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{1, 1, 2}, {0, 1, 2}};
  const Adjacency fn = face_neighbors(m, edge_topology(m));
  ASSERT_EQ(fn.size(), 2u);
  ASSERT_GE(fn.degree(0), 1u);
  for (auto g = fn.begin(0); g != fn.end(0); ++g) EXPECT_EQ(*g, 1u);
  ASSERT_GE(fn.degree(1), 1u);
  for (auto g = fn.begin(1); g != fn.end(1); ++g) EXPECT_EQ(*g, 0u);
}

TEST(MeshTest, VertexComponents) {
  std::vector<std::uint32_t> comp;
  EXPECT_EQ(vertex_components(box(), comp), 1u);
  EXPECT_EQ(comp, std::vector<std::uint32_t>(8, 0));

  Mesh two = merged(box(), box({3, 0, 0}, {4, 1, 1}));
  EXPECT_EQ(vertex_components(two, comp), 2u);
  ASSERT_EQ(comp.size(), 16u);
  for (int v = 0; v < 8; ++v) EXPECT_EQ(comp[v], 0u);
  for (int v = 8; v < 16; ++v) EXPECT_EQ(comp[v], 1u);

  two.positions.push_back({9, 9, 9});  // an isolated vertex is its own component
  EXPECT_EQ(vertex_components(two, comp), 3u);
  EXPECT_EQ(comp.back(), 2u);

  EXPECT_EQ(vertex_components(Mesh{}, comp), 0u);
  EXPECT_TRUE(comp.empty());
}

TEST(MeshTest, WithPerVertexAttributesIsIdentityWhenAlreadyPerVertex) {
  Mesh m = box();
  m.colors.assign(8, Color{1, 2, 3, 4});
  const Mesh out = with_per_vertex_attributes(m);
  EXPECT_EQ(out.positions, m.positions);
  EXPECT_EQ(out.faces, m.faces);
  EXPECT_EQ(out.colors, m.colors);
}

TEST(MeshTest, WithPerVertexAttributesSplitsSeams) {
  // A quad of two triangles; the UV of vertex 2 differs between them.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 2, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5f, 0.5f}};
  m.uv_faces = {{0, 1, 2}, {0, 4, 3}};
  m.colors = {{10, 0, 0, 255}, {20, 0, 0, 255}, {30, 0, 0, 255}, {40, 0, 0, 255}};
  ASSERT_NO_THROW(m.validate());
  const Mesh out = with_per_vertex_attributes(m);
  ASSERT_NO_THROW(out.validate());
  EXPECT_TRUE(out.attributes_per_vertex());
  ASSERT_EQ(out.num_vertices(), 5u);  // vertex 2 is split in two
  ASSERT_EQ(out.num_faces(), 2u);
  ASSERT_EQ(out.uvs.size(), 5u);
  ASSERT_EQ(out.colors.size(), 5u);
  EXPECT_TRUE(out.normals.empty());
  // Each corner keeps its position, UV and colour.
  for (std::size_t f = 0; f < 2; ++f)
    for (int k = 0; k < 3; ++k) {
      const Index nv = out.faces[f][k];
      EXPECT_EQ(out.positions[nv], m.positions[m.faces[f][k]]);
      EXPECT_EQ(out.uvs[nv], m.uvs[m.uv_faces[f][k]]);
      EXPECT_EQ(out.colors[nv], m.colors[m.faces[f][k]]);
    }
  // The shared corner 0 (same UV in both faces) stays one vertex; 2 does not.
  EXPECT_EQ(out.faces[0][0], out.faces[1][0]);
  EXPECT_NE(out.faces[0][2], out.faces[1][1]);
}

TEST(MeshTest, WithPerVertexAttributesOnBoxWithFaceUVs) {
  // Each box side gets its own four UVs (a cube map): 6 x 4 = 24 vertices.
  Mesh m = box();
  std::map<std::pair<int, Index>, Index> uv_of;  // (side, position) -> uv index
  m.uv_faces.resize(m.num_faces());
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const auto key = std::make_pair(int(f / 2), m.faces[f][k]);
      auto [it, fresh] = uv_of.try_emplace(key, Index(m.uvs.size()));
      if (fresh) m.uvs.push_back({float(key.first), float(key.second)});
      m.uv_faces[f][k] = it->second;
    }
  ASSERT_EQ(m.uvs.size(), 24u);
  // Normals per face corner too: the face normal, one per side.
  const auto fn = face_normals(m);
  for (int side = 0; side < 6; ++side) m.normals.push_back(to_float(fn[2 * side]));
  for (std::size_t f = 0; f < m.num_faces(); ++f) {
    const Index n = Index(f / 2);
    m.normal_faces.push_back({n, n, n});
  }
  ASSERT_NO_THROW(m.validate());

  const Mesh out = with_per_vertex_attributes(m);
  ASSERT_NO_THROW(out.validate());
  EXPECT_EQ(out.num_vertices(), 24u);
  EXPECT_EQ(out.num_faces(), 12u);
  EXPECT_EQ(out.normals.size(), 24u);
  EXPECT_EQ(out.uvs.size(), 24u);
  EXPECT_TRUE(out.attributes_per_vertex());
  for (std::size_t f = 0; f < out.num_faces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Index v = out.faces[f][k];
      EXPECT_EQ(out.positions[v], m.positions[m.faces[f][k]]);
      EXPECT_EQ(out.normals[v], m.normals[f / 2]);
      EXPECT_EQ(out.uvs[v], m.uvs[m.uv_faces[f][k]]);
    }
  // Geometry is unchanged: same area; the seams now cut it into six pieces.
  const MeshReport r = mesh_report(out);
  EXPECT_NEAR(r.area, 6.0, 1e-12);
  EXPECT_EQ(r.components, 6u);
  EXPECT_EQ(r.boundary_loops, 6u);
}

TEST(MeshTest, SubdivideMidpointBox) {
  const Mesh m = box();
  const EdgeTopology topo = edge_topology(m);
  const Mesh s = subdivide_midpoint(m);
  EXPECT_EQ(s.num_faces(), 4 * m.num_faces());
  EXPECT_EQ(s.num_vertices(), m.num_vertices() + topo.edges.size());  // 8 + 18
  ASSERT_NO_THROW(s.validate());
  // Old vertices keep their place; new ones are edge midpoints.
  for (std::size_t v = 0; v < m.num_vertices(); ++v) EXPECT_EQ(s.positions[v], m.positions[v]);
  for (std::size_t e = 0; e < topo.edges.size(); ++e)
    EXPECT_EQ(s.positions[m.num_vertices() + e], (m.positions[topo.edges[e][0]] + m.positions[topo.edges[e][1]]) * 0.5);
  const MeshReport before = mesh_report(m), after = mesh_report(s);
  EXPECT_NEAR(after.area, 6.0, 1e-12);
  EXPECT_TRUE(after.closed);
  EXPECT_TRUE(after.oriented);
  EXPECT_EQ(after.genus, before.genus);
  EXPECT_EQ(after.edges, 2 * before.edges + 3 * before.faces);  // 72
  ASSERT_TRUE(after.volume.has_value());
  EXPECT_NEAR(*after.volume, 1.0, 1e-12);
  // Orientation kept: normals of the children equal the parent's.
  const auto pn = face_normals(m), cn = face_normals(s);
  for (std::size_t f = 0; f < m.num_faces(); ++f)
    for (int c = 0; c < 4; ++c) EXPECT_NEAR(dot(pn[f], cn[4 * f + c]), 1.0, 1e-12);
}

TEST(MeshTest, SubdivideMidpointKeepsTorusGenusAndArea) {
  const Mesh m = torus(2.0, 0.5, 16, 8);
  const Mesh s = subdivide_midpoint(m);
  const MeshReport before = mesh_report(m), after = mesh_report(s);
  EXPECT_EQ(after.faces, 4 * before.faces);
  EXPECT_EQ(after.vertices, before.vertices + before.edges);
  EXPECT_NEAR(after.area, before.area, 1e-9 * before.area);
  EXPECT_TRUE(after.closed);
  ASSERT_TRUE(after.genus.has_value());
  EXPECT_EQ(*after.genus, 1);
  EXPECT_EQ(after.euler_characteristic, 0);
}

TEST(MeshTest, SubdivideMidpointGridStaysOpen) {
  const Mesh s = subdivide_midpoint(grid(2));
  const MeshReport r = mesh_report(s);
  EXPECT_EQ(r.faces, 32u);
  EXPECT_EQ(r.vertices, 25u);  // the same as grid(4)
  EXPECT_EQ(r.boundary_loops, 1u);
  EXPECT_EQ(r.boundary_edges, 16u);
  EXPECT_FALSE(r.closed);
  EXPECT_EQ(r.genus, 0);
  EXPECT_NEAR(r.area, 4.0, 1e-12);
}

TEST(MeshTest, SubdivideMidpointKeepsDegenerateFace) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  m.faces = {{0, 1, 2}, {0, 0, 1}};
  const Mesh s = subdivide_midpoint(m);
  EXPECT_EQ(s.num_faces(), 5u);
  EXPECT_EQ(s.faces.back(), (Tri{0, 0, 1}));
  EXPECT_NO_THROW(s.validate());
}

TEST(MeshTest, SubdivideMidpointDropsAttributes) {
  Mesh m = box();
  m.colors.assign(8, Color{});
  m.normals.assign(8, Vec3f{0, 0, 1});
  const Mesh s = subdivide_midpoint(m);
  EXPECT_FALSE(s.has_colors());
  EXPECT_FALSE(s.has_normals());
  EXPECT_NO_THROW(s.validate());
}

// The message of the InvalidInput that validate() throws ("" if none).
std::string validate_error(const Mesh& m) {
  try {
    m.validate();
  } catch (const InvalidInput& e) {
    return e.what();
  } catch (const std::exception& e) {
    return std::string("wrong exception type: ") + e.what();
  }
  return "";
}

TEST(MeshTest, ValidateAcceptsGoodMeshes) {
  EXPECT_NO_THROW(box().validate());
  EXPECT_NO_THROW(Mesh{}.validate());
  Mesh m = box();
  m.normals.assign(8, {});
  m.uvs.assign(8, {});
  m.colors.assign(8, {});
  EXPECT_NO_THROW(m.validate());
}

TEST(MeshTest, ValidateOutOfRangeIndex) {
  Mesh m = box();
  m.faces[0][1] = 8;
  const std::string msg = validate_error(m);
  EXPECT_NE(msg.find("face 0"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vertex 8"), std::string::npos) << msg;
  EXPECT_NE(msg.find("only 8"), std::string::npos) << msg;

  Mesh late = box();
  late.faces[7][2] = 1000;
  const std::string msg7 = validate_error(late);
  EXPECT_NE(msg7.find("face 7"), std::string::npos) << msg7;
  EXPECT_NE(msg7.find("1000"), std::string::npos) << msg7;
}

TEST(MeshTest, ValidateNonFiniteCoordinate) {
  Mesh m = box();
  m.positions[3].y = std::numeric_limits<double>::quiet_NaN();
  std::string msg = validate_error(m);
  EXPECT_NE(msg.find("vertex 3"), std::string::npos) << msg;
  EXPECT_NE(msg.find("non-finite"), std::string::npos) << msg;

  m = box();
  m.positions[5].z = std::numeric_limits<double>::infinity();
  msg = validate_error(m);
  EXPECT_NE(msg.find("vertex 5"), std::string::npos) << msg;
}

TEST(MeshTest, ValidateWrongAttributeLengths) {
  Mesh m = box();
  m.colors.assign(7, {});
  std::string msg = validate_error(m);
  EXPECT_NE(msg.find("7 colours"), std::string::npos) << msg;
  EXPECT_NE(msg.find("8 vertices"), std::string::npos) << msg;

  m = box();
  m.normals.assign(9, {});
  msg = validate_error(m);
  EXPECT_NE(msg.find("9 normals"), std::string::npos) << msg;

  m = box();
  m.uvs.assign(2, {});
  msg = validate_error(m);
  EXPECT_NE(msg.find("2 uvs"), std::string::npos) << msg;

  m = box();
  m.uvs.assign(3, {});
  m.uv_faces.assign(11, {0, 1, 2});  // one short
  msg = validate_error(m);
  EXPECT_NE(msg.find("uv index triangles"), std::string::npos) << msg;

  m = box();
  m.normals.assign(3, {});
  m.normal_faces.assign(12, {0, 1, 2});
  m.normal_faces[4][2] = 3;
  msg = validate_error(m);
  EXPECT_NE(msg.find("face 4"), std::string::npos) << msg;
  EXPECT_NE(msg.find("normal 3"), std::string::npos) << msg;
}

}  // namespace
}  // namespace cgview
