// repair on what no halfedge structure holds (three faces on an edge, a
// bowtie), on duplicate and degenerate faces and on a box split into
// separate triangles; a manifold mesh comes back as it was.
#include "filters/repair.h"

#include <gtest/gtest.h>

#include "core/mesh_report.h"
#include "filter_shapes.h"
#include "test_support.h"

namespace cgview {
namespace {

// Two triangles that share only a vertex.
Mesh bowtie() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  return m;
}

TEST(RepairTest, ThreeFacesOnAnEdgeBecomeManifold) {
  const Mesh in = test::non_manifold();
  ASSERT_FALSE(mesh_report(in).manifold);
  const RepairResult r = repair(in);
  const Mesh& out = r.mesh;
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.manifold);
  EXPECT_TRUE(rep.oriented);
  EXPECT_EQ(out.num_faces(), 3u);
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("manifold_before"), 0);
  EXPECT_EQ(m.at("manifold_after"), 1);
  EXPECT_GE(m.at("vertices_duplicated"), 2);
}

TEST(RepairTest, BowtieBecomesManifold) {
  const Mesh in = bowtie();
  ASSERT_FALSE(mesh_report(in).manifold);
  const RepairResult r = repair(in);
  const Mesh& out = r.mesh;
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.manifold);
  EXPECT_EQ(out.num_faces(), 2u);
  EXPECT_EQ(out.num_vertices(), 6u);
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("vertices_duplicated"), 1);
  EXPECT_EQ(m.at("manifold_before"), 0);
  EXPECT_EQ(m.at("manifold_after"), 1);
}

TEST(RepairTest, DuplicateAndDegenerateFacesAreRemoved) {
  Mesh in = test::box();
  const std::size_t faces = in.num_faces();
  in.faces.push_back(in.faces[0]);                                       // the same face again
  in.faces.push_back({in.faces[1][1], in.faces[1][2], in.faces[1][0]});  // rotated copy
  in.faces.push_back({0, 0, 1});                                         // a repeated vertex
  in.positions.push_back({0.5, 0, 0});                                   // collinear with 0 and 1
  in.faces.push_back({0, 1, Index(in.positions.size() - 1)});            // zero area
  in.positions.push_back({5, 5, 5});                                     // used by no face
  ASSERT_GT(mesh_report(in).duplicate_faces + mesh_report(in).degenerate_faces, 0u);
  const RepairResult r = repair(in);
  const Mesh& out = r.mesh;
  EXPECT_EQ(out.num_faces(), faces);
  EXPECT_EQ(out.num_vertices(), 8u);
  const MeshReport rep = mesh_report(out);
  EXPECT_EQ(rep.duplicate_faces, 0u);
  EXPECT_EQ(rep.degenerate_faces, 0u);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.oriented);
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("faces_removed"), 4);
  EXPECT_EQ(m.at("closed_after"), 1);
}

TEST(RepairTest, SplitBoxIsWeldedAndClosed) {
  const Mesh box = test::box();
  Mesh in;
  for (const Tri& f : box.faces) {
    const Index base = Index(in.positions.size());
    for (Index v : f) in.positions.push_back(box.positions[v]);
    in.faces.push_back({base, base + 1, base + 2});
  }
  ASSERT_EQ(in.num_vertices(), 36u);
  ASSERT_FALSE(mesh_report(in).closed);
  const RepairResult r = repair(in);
  const Mesh& out = r.mesh;
  EXPECT_EQ(out.num_vertices(), 8u);
  EXPECT_EQ(out.num_faces(), 12u);
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.oriented);
  EXPECT_EQ(rep.genus, 0);
  ASSERT_TRUE(rep.volume.has_value());
  EXPECT_NEAR(*rep.volume, 1.0, 1e-9);
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("vertices_merged"), 28);
  EXPECT_EQ(m.at("closed_before"), 0);
  EXPECT_EQ(m.at("closed_after"), 1);
}

TEST(RepairTest, ManifoldInputIsUnchanged) {
  const Mesh in = test::torus();
  const RepairResult r = repair(in);
  const Mesh& out = r.mesh;
  EXPECT_EQ(out.num_vertices(), in.num_vertices());
  EXPECT_EQ(out.num_faces(), in.num_faces());
  const Metrics& m = r.metrics;
  EXPECT_EQ(m.at("faces_removed"), 0);
  EXPECT_EQ(m.at("vertices_merged"), 0);
  EXPECT_EQ(m.at("vertices_duplicated"), 0);
}

}  // namespace
}  // namespace cgview
