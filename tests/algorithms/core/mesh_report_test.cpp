// mesh_report: analytic shapes with known answers, defects one at a time,
// and invariants over real sample meshes checked against CGAL's own counts.
#include "core/mesh_report.h"

#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>

#include <cmath>
#include <iterator>
#include <numbers>
#include <vector>

#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using test::box;
using test::grid;
using test::torus;
using test::uv_sphere;

using test::merged;

// The defining formulas of the report, which every result must satisfy.
void expect_consistent(const MeshReport& r, const std::string& what) {
  SCOPED_TRACE(what);
  ASSERT_TRUE(r.euler_characteristic.has_value());
  EXPECT_EQ(*r.euler_characteristic,
            std::int64_t(r.vertices - r.isolated_vertices) - std::int64_t(r.edges) + std::int64_t(r.faces));
  if (r.genus) {
    EXPECT_TRUE(r.manifold);
    EXPECT_TRUE(r.oriented);
    EXPECT_GE(*r.genus, 0);
    EXPECT_EQ(2 * *r.genus, 2 * std::int64_t(r.components) - *r.euler_characteristic - std::int64_t(r.boundary_loops));
  }
  EXPECT_EQ(r.manifold, r.non_manifold_edges == 0 && r.non_manifold_vertices == 0);
  if (r.closed) {
    EXPECT_TRUE(r.manifold);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_EQ(r.boundary_loops, 0u);
  }
  if (r.oriented) {
    EXPECT_EQ(r.inconsistent_edges, 0u);
  }
  EXPECT_EQ(r.volume.has_value(), r.closed && r.oriented);
  EXPECT_LE(r.boundary_loops, r.boundary_edges);
}

TEST(MeshReportTest, Box) {
  const MeshReport r = mesh_report(box());
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.faces, 12u);
  EXPECT_EQ(r.edges, 18u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.isolated_vertices, 0u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.boundary_loops, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.degenerate_faces, 0u);
  EXPECT_EQ(r.duplicate_faces, 0u);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  EXPECT_NEAR(r.area, 6.0, 1e-12);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_NEAR(*r.volume, 1.0, 1e-12);
  EXPECT_EQ(r.bbox.min, (Vec3{0, 0, 0}));
  EXPECT_EQ(r.bbox.max, (Vec3{1, 1, 1}));
  expect_consistent(r, "box");
}

TEST(MeshReportTest, BoxVolumeDoesNotDependOnPlacement) {
  const MeshReport r = mesh_report(box({10, -20, 30}, {12, -17, 34}));
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_NEAR(*r.volume, 24.0, 1e-9);
  EXPECT_NEAR(r.area, 2 * (6.0 + 8.0 + 12.0), 1e-9);
}

TEST(MeshReportTest, InsideOutBoxHasNegativeVolume) {
  Mesh m = box();
  for (Tri& t : m.faces) std::swap(t[1], t[2]);
  const MeshReport r = mesh_report(m);
  EXPECT_TRUE(r.oriented);  // consistently, just the other way round
  EXPECT_EQ(r.genus, 0);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_NEAR(*r.volume, -1.0, 1e-12);
}

TEST(MeshReportTest, UvSphere) {
  const double radius = 2.0;
  const MeshReport r = mesh_report(uv_sphere(radius, 16, 32));
  EXPECT_EQ(r.vertices, 2u + 15u * 32u);
  EXPECT_EQ(r.faces, 2u * 32u * 15u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  const double pi = std::numbers::pi;
  ASSERT_TRUE(r.volume.has_value());
  const double want_v = 4.0 / 3.0 * pi * radius * radius * radius;
  EXPECT_GT(*r.volume, 0.95 * want_v);
  EXPECT_LT(*r.volume, want_v);  // an inscribed polyhedron is smaller
  EXPECT_NEAR(r.area, 4 * pi * radius * radius, 0.03 * 4 * pi * radius * radius);
  expect_consistent(r, "uv_sphere");
}

TEST(MeshReportTest, Torus) {
  const MeshReport r = mesh_report(torus(2.0, 0.5, 24, 12));
  EXPECT_EQ(r.vertices, 288u);
  EXPECT_EQ(r.faces, 576u);
  EXPECT_EQ(r.edges, 864u);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.genus, 1);
  // The 24 x 12 polyhedron is inscribed: about 5.6% smaller than the torus.
  const double pi = std::numbers::pi;
  const double want_v = 2 * pi * pi * 2.0 * 0.5 * 0.5;
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_LT(*r.volume, want_v);
  EXPECT_GT(*r.volume, 0.9 * want_v);
  EXPECT_NEAR(r.area, 4 * pi * pi * 2.0 * 0.5, 0.05 * 4 * pi * pi * 2.0 * 0.5);
  expect_consistent(r, "torus");
}

TEST(MeshReportTest, FineTorusVolumeAndArea) {
  const double R = 3.0, r0 = 1.0, pi = std::numbers::pi;
  const MeshReport r = mesh_report(torus(R, r0, 128, 64));
  EXPECT_EQ(r.genus, 1);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_NEAR(*r.volume, 2 * pi * pi * R * r0 * r0, 0.005 * 2 * pi * pi * R * r0 * r0);
  EXPECT_NEAR(r.area, 4 * pi * pi * R * r0, 0.005 * 4 * pi * pi * R * r0);
}

TEST(MeshReportTest, Grid) {
  const MeshReport r = mesh_report(grid(4));
  EXPECT_EQ(r.vertices, 25u);
  EXPECT_EQ(r.faces, 32u);
  EXPECT_EQ(r.edges, 56u);
  EXPECT_EQ(r.boundary_edges, 16u);
  EXPECT_EQ(r.boundary_loops, 1u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.genus, 0);
  EXPECT_NEAR(r.area, 16.0, 1e-12);
  EXPECT_FALSE(r.volume.has_value());
  expect_consistent(r, "grid");
}

TEST(MeshReportTest, TwoBoxes) {
  const MeshReport r = mesh_report(merged(box(), box({2, 2, 2}, {3, 3, 3})));
  EXPECT_EQ(r.vertices, 16u);
  EXPECT_EQ(r.faces, 24u);
  EXPECT_EQ(r.edges, 36u);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_EQ(r.genus, 0);
  EXPECT_TRUE(r.closed);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_NEAR(*r.volume, 2.0, 1e-12);
  expect_consistent(r, "two boxes");
}

TEST(MeshReportTest, BoxAndTorus) {
  const MeshReport r = mesh_report(merged(box({5, 5, 5}, {6, 6, 6}), torus()));
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 1);  // summed over the components
  expect_consistent(r, "box and torus");
}

TEST(MeshReportTest, OpenBox) {
  Mesh m = box();
  m.faces.erase(m.faces.begin());
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.faces, 11u);
  EXPECT_EQ(r.edges, 18u);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(r.boundary_loops, 1u);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.genus, 0);
  EXPECT_FALSE(r.volume.has_value());
  EXPECT_NEAR(r.area, 5.5, 1e-12);
  expect_consistent(r, "open box");
}

TEST(MeshReportTest, BoxWithTwoHoles) {
  Mesh m = box();
  // Remove one triangle from the bottom (faces 0, 1) and one from the top (2, 3).
  m.faces.erase(m.faces.begin() + 2);
  m.faces.erase(m.faces.begin());
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_EQ(r.boundary_loops, 2u);
  EXPECT_EQ(r.genus, 0);
  expect_consistent(r, "box with two holes");
}

TEST(MeshReportTest, FlippedFace) {
  Mesh m = box();
  std::swap(m.faces[0][1], m.faces[0][2]);
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_TRUE(r.manifold);
  EXPECT_FALSE(r.oriented);
  EXPECT_FALSE(r.genus.has_value());
  EXPECT_FALSE(r.volume.has_value());
  EXPECT_EQ(r.euler_characteristic, 2);
  expect_consistent(r, "flipped face");
}

TEST(MeshReportTest, NonManifoldEdge) {
  // Three triangles hinged on the edge 0-1.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.edges, 7u);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_FALSE(r.manifold);
  EXPECT_FALSE(r.closed);
  EXPECT_FALSE(r.oriented);
  EXPECT_FALSE(r.genus.has_value());
  EXPECT_EQ(r.components, 1u);
  expect_consistent(r, "non-manifold edge");
}

TEST(MeshReportTest, BowtieVertex) {
  // Two triangles sharing vertex 0 only.
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_FALSE(r.manifold);
  EXPECT_FALSE(r.genus.has_value());
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.edges, 6u);
  expect_consistent(r, "bowtie");
}

TEST(MeshReportTest, TwoCubesSharingACorner) {
  // Two closed boxes touching at one vertex: that vertex has two fans.
  Mesh a = box(), b = box({1, 1, 1}, {2, 2, 2});
  Mesh m = a;
  std::vector<Index> id(8);
  for (Index v = 0; v < 8; ++v) {
    if (v == 0) {
      id[v] = 7;
      continue;
    }  // b's (1,1,1) is a's vertex 7
    id[v] = Index(m.positions.size());
    m.positions.push_back(b.positions[v]);
  }
  for (Tri t : b.faces) m.faces.push_back({id[t[0]], id[t[1]], id[t[2]]});
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.vertices, 15u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_FALSE(r.manifold);
  EXPECT_FALSE(r.closed);
  expect_consistent(r, "two cubes on a corner");
}

TEST(MeshReportTest, DegenerateFaces) {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}};
  m.faces = {{0, 1, 2}, {0, 0, 2}, {0, 1, 3}};  // good, repeated index, collinear
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.degenerate_faces, 2u);
  EXPECT_EQ(r.duplicate_faces, 0u);
  EXPECT_NEAR(r.area, 0.5, 1e-15);
  expect_consistent(r, "degenerate faces");

  Mesh clean = box();
  EXPECT_EQ(mesh_report(clean).degenerate_faces, 0u);
  clean.faces.push_back({3, 3, 3});
  EXPECT_EQ(mesh_report(clean).degenerate_faces, 1u);
}

TEST(MeshReportTest, DegenerateThresholdScalesWithSize) {
  // A tiny but proper triangle on a tiny mesh is not degenerate.
  Mesh m;
  m.positions = {{0, 0, 0}, {1e-6, 0, 0}, {0, 1e-6, 0}};
  m.faces = {{0, 1, 2}};
  EXPECT_EQ(mesh_report(m).degenerate_faces, 0u);
}

TEST(MeshReportTest, DuplicateFaces) {
  Mesh m = box();
  m.faces.push_back(m.faces[0]);                                     // the same
  m.faces.push_back({m.faces[5][2], m.faces[5][0], m.faces[5][1]});  // rotated
  m.faces.push_back({m.faces[7][0], m.faces[7][2], m.faces[7][1]});  // reversed
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.duplicate_faces, 3u);
  EXPECT_EQ(r.faces, 15u);
  EXPECT_EQ(r.edges, 18u);
  EXPECT_GT(r.non_manifold_edges, 0u);  // each copied side now has three faces
  EXPECT_FALSE(r.manifold);
  expect_consistent(r, "duplicate faces");
}

TEST(MeshReportTest, IsolatedVertices) {
  Mesh m = box();
  m.positions.push_back({5, 5, 5});
  m.positions.push_back({-5, 0, 0});
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.vertices, 10u);
  EXPECT_EQ(r.isolated_vertices, 2u);
  EXPECT_EQ(r.components, 1u);           // isolated vertices are not components
  EXPECT_EQ(r.euler_characteristic, 2);  // nor counted in chi
  EXPECT_EQ(r.genus, 0);
  EXPECT_TRUE(r.closed);
  EXPECT_EQ(r.bbox.min.x, -5.0);  // but they are in the bounding box
  EXPECT_EQ(r.bbox.max.z, 5.0);
  expect_consistent(r, "isolated vertices");
}

TEST(MeshReportTest, EmptyAndPointCloud) {
  const MeshReport e = mesh_report(Mesh{});
  EXPECT_EQ(e.vertices, 0u);
  EXPECT_EQ(e.faces, 0u);
  EXPECT_EQ(e.components, 0u);
  EXPECT_TRUE(e.bbox.empty());
  EXPECT_FALSE(e.closed);
  EXPECT_FALSE(e.genus.has_value());
  EXPECT_FALSE(e.volume.has_value());

  Mesh pts;
  pts.positions = {{0, 0, 0}, {1, 2, 3}};
  const MeshReport p = mesh_report(pts);
  EXPECT_EQ(p.vertices, 2u);
  EXPECT_EQ(p.isolated_vertices, 2u);
  EXPECT_EQ(p.components, 0u);
  EXPECT_EQ(p.edges, 0u);
  EXPECT_FALSE(p.genus.has_value());
  EXPECT_EQ(p.euler_characteristic, 0);
}

TEST(MeshReportTest, SingleTriangle) {
  Mesh m;
  m.positions = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}};
  m.faces = {{0, 1, 2}};
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.edges, 3u);
  EXPECT_EQ(r.boundary_edges, 3u);
  EXPECT_EQ(r.boundary_loops, 1u);
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_EQ(r.genus, 0);
  EXPECT_NEAR(r.area, 2.0, 1e-15);
  expect_consistent(r, "triangle");
}

// ---- Real meshes against CGAL ---------------------------------------------

struct CgalCounts {
  std::size_t vertices, faces, edges, components, border_cycles;
};

CgalCounts cgal_counts(SurfaceMesh& sm) {
  CgalCounts c{};
  c.vertices = num_vertices(sm);
  c.faces = num_faces(sm);
  c.edges = num_edges(sm);
  auto fcc = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:cc", 0).first;
  c.components = PMP::connected_components(sm, fcc);
  std::vector<SurfaceMesh::Halfedge_index> cycles;
  PMP::extract_boundary_cycles(sm, std::back_inserter(cycles));
  c.border_cycles = cycles.size();
  return c;
}

TEST(MeshReportTest, ElephantReference) {
  const Mesh m = read_mesh(test::sample("elephant.off"));
  const MeshReport r = mesh_report(m);
  EXPECT_EQ(r.vertices, 2775u);
  EXPECT_EQ(r.faces, 5558u);
  EXPECT_EQ(r.edges, 8337u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.boundary_loops, 0u);
  EXPECT_TRUE(r.manifold);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.oriented);
  EXPECT_EQ(r.euler_characteristic, -4);
  EXPECT_EQ(r.genus, 3);
  ASSERT_TRUE(r.volume.has_value());
  EXPECT_GT(*r.volume, 0.0);  // outward oriented

  SurfaceMeshResult s = to_surface_mesh(m);
  ASSERT_EQ(s.skipped_faces, 0u);
  const CgalCounts c = cgal_counts(s.mesh);
  EXPECT_EQ(c.vertices, 2775u);
  EXPECT_EQ(c.faces, 5558u);
  EXPECT_EQ(c.edges, 8337u);
  EXPECT_EQ(c.components, 1u);
  EXPECT_EQ(c.border_cycles, 0u);
}

TEST(MeshReportTest, SampleFamilyInvariantsAgreeWithCgal) {
  int compared = 0;
  for (const auto& path : test::sample_family()) {
    SCOPED_TRACE(path.filename().string());
    const Mesh m = read_mesh(path);
    const MeshReport r = mesh_report(m);
    EXPECT_EQ(r.vertices, m.num_vertices());
    EXPECT_EQ(r.faces, m.num_faces());
    EXPECT_GT(r.faces, 0u);
    EXPECT_GT(r.area, 0.0);
    expect_consistent(r, path.filename().string());

    SurfaceMeshResult s = to_surface_mesh(m);
    if (s.skipped_faces != 0 || !r.manifold) continue;
    ++compared;
    ASSERT_TRUE(s.mesh.is_valid(false));
    const CgalCounts c = cgal_counts(s.mesh);
    EXPECT_EQ(r.vertices, c.vertices);
    EXPECT_EQ(r.faces, c.faces);
    EXPECT_EQ(r.edges, c.edges);
    EXPECT_EQ(r.components, c.components);
    EXPECT_EQ(r.boundary_loops, c.border_cycles);
    EXPECT_EQ(r.closed, CGAL::is_closed(s.mesh) && r.faces > 0);
    // A Surface_mesh built without skipped faces is consistently oriented.
    EXPECT_TRUE(r.oriented);
    EXPECT_TRUE(r.genus.has_value());
  }
  EXPECT_GE(compared, 8);
}

TEST(MeshReportTest, KnownSampleTopology) {
  struct Want {
    const char* file;
    std::uint64_t vertices, faces, isolated;
    std::int64_t genus;
    std::uint64_t boundary_loops;
  };
  for (const Want& w : {Want{"cube.off", 8, 12, 0, 0, 0}, Want{"sphere.off", 162, 320, 0, 0, 0},
                        Want{"cube-ouvert.off", 9, 10, 1, 0, 1},
                        Want{"double-torus-example.off", 231, 466, 0, 2, 0},  // 220 polygons, triangulated
                        Want{"colored_tetra.ply", 4, 4, 0, 0, 0}}) {
    SCOPED_TRACE(w.file);
    const MeshReport r = mesh_report(read_mesh(test::sample(w.file)));
    EXPECT_EQ(r.vertices, w.vertices);
    EXPECT_EQ(r.faces, w.faces);
    EXPECT_EQ(r.isolated_vertices, w.isolated);
    EXPECT_EQ(r.genus, w.genus);
    EXPECT_EQ(r.boundary_loops, w.boundary_loops);
    EXPECT_EQ(r.components, 1u);
    EXPECT_TRUE(r.manifold);
    EXPECT_EQ(r.closed, w.boundary_loops == 0);
  }
}

}  // namespace
}  // namespace cgview
