// The CGAL bridge: Mesh <-> CGAL::Surface_mesh.
#include "core/surface_mesh.h"

#include <gtest/gtest.h>

#include <CGAL/IO/Color.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <tuple>
#include <vector>

#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

TEST(SurfaceMeshTest, BoxRoundTrip) {
  const Mesh m = test::box({-1, 0, 2}, {1, 3, 5});
  SurfaceMeshResult r = to_surface_mesh(m);
  EXPECT_EQ(r.skipped_faces, 0u);
  EXPECT_EQ(r.mesh.number_of_vertices(), 8u);
  EXPECT_EQ(r.mesh.number_of_faces(), 12u);
  EXPECT_EQ(r.mesh.number_of_edges(), 18u);
  EXPECT_TRUE(r.mesh.is_valid(false));
  EXPECT_TRUE(CGAL::is_closed(r.mesh));
  EXPECT_TRUE(CGAL::is_triangle_mesh(r.mesh));
  // Vertices keep their indices.
  for (Index v = 0; v < 8; ++v) {
    const Point3& p = r.mesh.point(SurfaceMesh::Vertex_index(v));
    EXPECT_EQ(p.x(), m.positions[v].x);
    EXPECT_EQ(p.y(), m.positions[v].y);
    EXPECT_EQ(p.z(), m.positions[v].z);
  }
  const Mesh back = from_surface_mesh(r.mesh);
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.faces.size(), m.faces.size());
  // Each face comes back as the same cyclic triangle (CGAL may start it at
  // another corner).
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    const Tri& a = m.faces[f];
    const Tri& b = back.faces[f];
    const bool same = (b == a) || (b == Tri{a[1], a[2], a[0]}) || (b == Tri{a[2], a[0], a[1]});
    EXPECT_TRUE(same) << "face " << f;
  }
}

TEST(SurfaceMeshTest, ElephantRoundTrip) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  SurfaceMeshResult r = to_surface_mesh(m);
  EXPECT_EQ(r.skipped_faces, 0u);
  EXPECT_EQ(r.mesh.number_of_vertices(), m.num_vertices());
  EXPECT_EQ(r.mesh.number_of_faces(), m.num_faces());
  EXPECT_EQ(r.mesh.number_of_edges(), 8337u);
  EXPECT_TRUE(r.mesh.is_valid(false));
  EXPECT_TRUE(CGAL::is_closed(r.mesh));

  const Mesh back = from_surface_mesh(r.mesh);
  EXPECT_EQ(back.num_vertices(), 2775u);
  EXPECT_EQ(back.num_faces(), 5558u);
  EXPECT_EQ(back.positions, m.positions);
  const MeshReport a = mesh_report(m), b = mesh_report(back);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.genus, b.genus);
  EXPECT_EQ(b.genus, 3);
  EXPECT_NEAR(a.area, b.area, 1e-12 * a.area);
  ASSERT_TRUE(a.volume && b.volume);
  EXPECT_NEAR(*a.volume, *b.volume, 1e-12 * std::abs(*a.volume));
}

TEST(SurfaceMeshTest, OpenMeshIsNotClosed) {
  const Mesh g = test::grid(3);
  SurfaceMeshResult r = to_surface_mesh(g);
  EXPECT_EQ(r.skipped_faces, 0u);
  EXPECT_TRUE(r.mesh.is_valid(false));
  EXPECT_FALSE(CGAL::is_closed(r.mesh));
  const Mesh back = from_surface_mesh(r.mesh);
  EXPECT_EQ(back.num_faces(), g.num_faces());
}

TEST(SurfaceMeshTest, NonManifoldEdgeFaceIsSkipped) {
  // Three triangles on the edge 0-1: the third cannot be added.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  SurfaceMeshResult r = to_surface_mesh(m);
  EXPECT_EQ(r.skipped_faces, 1u);
  EXPECT_EQ(r.mesh.number_of_faces(), 2u);
  EXPECT_EQ(r.mesh.number_of_vertices(), 5u);  // vertices keep their indices, used or not
  EXPECT_TRUE(r.mesh.is_valid(false));
  const Mesh back = from_surface_mesh(r.mesh);
  EXPECT_EQ(back.num_faces(), 2u);
  EXPECT_EQ(back.num_vertices(), 5u);
}

TEST(SurfaceMeshTest, BadlyOrientedAndDegenerateFacesAreSkipped) {
  Mesh m = test::box();
  std::swap(m.faces[0][1], m.faces[0][2]);  // flipped against its neighbours
  m.faces.push_back({0, 0, 1});             // repeated index
  SurfaceMeshResult r = to_surface_mesh(m);
  EXPECT_GE(r.skipped_faces, 2u);
  EXPECT_EQ(r.mesh.number_of_faces() + r.skipped_faces, m.num_faces());
  EXPECT_TRUE(r.mesh.is_valid(false));
}

TEST(SurfaceMeshTest, NormalsAndColoursGoToPropertyMaps) {
  Mesh m = test::box();
  for (std::size_t v = 0; v < 8; ++v) {
    m.normals.push_back({float(v), 0, 1});
    m.colors.push_back({std::uint8_t(v * 10), 20, 30, 40});
  }
  SurfaceMeshResult r = to_surface_mesh(m);
  auto normals = r.mesh.property_map<SurfaceMesh::Vertex_index, Kernel::Vector_3>("v:normal");
  auto colors = r.mesh.property_map<SurfaceMesh::Vertex_index, CGAL::IO::Color>("v:color");
  ASSERT_TRUE(normals.second);
  ASSERT_TRUE(colors.second);
  for (Index v = 0; v < 8; ++v) {
    const auto n = normals.first[SurfaceMesh::Vertex_index(v)];
    EXPECT_EQ(n.x(), double(v));
    EXPECT_EQ(n.z(), 1.0);
    const auto c = colors.first[SurfaceMesh::Vertex_index(v)];
    EXPECT_EQ(int(c.red()), int(v * 10));
    EXPECT_EQ(int(c.green()), 20);
    EXPECT_EQ(int(c.blue()), 30);
    EXPECT_EQ(int(c.alpha()), 40);
  }
  // Without attributes there are no maps.
  SurfaceMeshResult plain = to_surface_mesh(test::box());
  EXPECT_FALSE((plain.mesh.property_map<SurfaceMesh::Vertex_index, Kernel::Vector_3>("v:normal").second));
  EXPECT_FALSE((plain.mesh.property_map<SurfaceMesh::Vertex_index, CGAL::IO::Color>("v:color").second));
}

TEST(SurfaceMeshTest, FromSurfaceMeshSkipsRemovedElements) {
  // Remove the three faces around box vertex 0 (faces 0, 4 and 8); CGAL then
  // removes vertex 0 too.  The copy back renumbers the remaining vertices,
  // with or without collect_garbage().
  const Mesh box = test::box();
  for (bool collect : {false, true}) {
    SCOPED_TRACE(collect ? "collected" : "with garbage");
    SurfaceMeshResult r = to_surface_mesh(box);
    SurfaceMesh& sm = r.mesh;
    for (Index f : {0u, 4u, 8u}) CGAL::Euler::remove_face(sm.halfedge(SurfaceMesh::Face_index(f)), sm);
    if (collect) sm.collect_garbage();
    ASSERT_EQ(sm.number_of_vertices(), 7u);
    ASSERT_EQ(sm.number_of_faces(), 9u);
    const Mesh back = from_surface_mesh(sm);
    EXPECT_EQ(back.num_vertices(), 7u);
    EXPECT_EQ(back.num_faces(), 9u);
    EXPECT_NO_THROW(back.validate());
    if (!collect) {  // the order is kept (collect_garbage() may move elements)
      for (std::size_t v = 0; v < 7; ++v) EXPECT_EQ(back.positions[v], box.positions[v + 1]);
    }
    // Either way each face keeps its corners' coordinates.
    std::vector<std::array<Vec3, 3>> got, want;
    for (const Tri& t : back.faces) got.push_back({back.positions[t[0]], back.positions[t[1]], back.positions[t[2]]});
    for (std::size_t f = 0; f < box.num_faces(); ++f)
      if (f != 0 && f != 4 && f != 8) {
        const Tri& t = box.faces[f];
        want.push_back({box.positions[t[0]], box.positions[t[1]], box.positions[t[2]]});
      }
    // Compare up to rotation of each triangle: rotate so the smallest point comes first.
    auto canon = [](std::vector<std::array<Vec3, 3>>& tris) {
      auto less = [](const Vec3& a, const Vec3& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
      for (auto& t : tris) {
        while (less(t[1], t[0]) || less(t[2], t[0])) std::rotate(t.begin(), t.begin() + 1, t.end());
      }
      std::sort(tris.begin(), tris.end(), [&](const auto& a, const auto& b) {
        return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end(), less);
      });
    };
    canon(got);
    canon(want);
    EXPECT_EQ(got, want);
    const MeshReport rep = mesh_report(back);
    EXPECT_EQ(rep.boundary_loops, 1u);
    EXPECT_EQ(rep.boundary_edges, 3u);
    EXPECT_EQ(rep.isolated_vertices, 0u);
    EXPECT_TRUE(rep.oriented);
    EXPECT_EQ(rep.genus, 0);
    EXPECT_NEAR(rep.area, 4.5, 1e-12);
  }
}

TEST(SurfaceMeshTest, FromSurfaceMeshTriangulatesNothing) {
  // A quad face is not a triangle: it is left out, not mangled.
  SurfaceMesh sm;
  auto a = sm.add_vertex({0, 0, 0}), b = sm.add_vertex({1, 0, 0}), c = sm.add_vertex({1, 1, 0}),
       d = sm.add_vertex({0, 1, 0}), e = sm.add_vertex({2, 0, 0});
  sm.add_face(a, b, c, d);
  sm.add_face(b, e, c);
  const Mesh m = from_surface_mesh(sm);
  EXPECT_EQ(m.num_vertices(), 5u);
  ASSERT_EQ(m.num_faces(), 1u);
  EXPECT_NO_THROW(m.validate());
}

}  // namespace
}  // namespace cgview
