// Everyday filters on CGAL, group C: repair, geodesic_distance and
// hausdorff, run through the registry on shapes with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "core/errors.h"
#include "core/mesh_report.h"
#include "registry/registry.h"
#include "algorithm_support.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::artifact;
using test::run_algorithm;
using test::Values;

// Three triangles on one edge.
Mesh three_on_an_edge() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

// Two triangles that share only a vertex.
Mesh bowtie() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  m.faces = {{0, 1, 2}, {0, 3, 4}};
  return m;
}

TEST(RepairTest, ThreeFacesOnAnEdgeBecomeManifold) {
  const Mesh in = three_on_an_edge();
  ASSERT_FALSE(mesh_report(in).manifold);
  const AlgorithmResult r = run_algorithm("repair", in);
  const Mesh& out = artifact<Mesh>(r, "mesh");
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.manifold);
  EXPECT_TRUE(rep.oriented);
  EXPECT_EQ(out.num_faces(), 3u);
  const Metrics& m = artifact<Metrics>(r, "metrics");
  EXPECT_EQ(m.at("manifold_before"), 0);
  EXPECT_EQ(m.at("manifold_after"), 1);
  EXPECT_GE(m.at("vertices_duplicated"), 2);
}

TEST(RepairTest, BowtieBecomesManifold) {
  const Mesh in = bowtie();
  ASSERT_FALSE(mesh_report(in).manifold);
  const AlgorithmResult r = run_algorithm("repair", in);
  const Mesh& out = artifact<Mesh>(r, "mesh");
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.manifold);
  EXPECT_EQ(out.num_faces(), 2u);
  EXPECT_EQ(out.num_vertices(), 6u);
  const Metrics& m = artifact<Metrics>(r, "metrics");
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
  const AlgorithmResult r = run_algorithm("repair", in);
  const Mesh& out = artifact<Mesh>(r, "mesh");
  EXPECT_EQ(out.num_faces(), faces);
  EXPECT_EQ(out.num_vertices(), 8u);
  const MeshReport rep = mesh_report(out);
  EXPECT_EQ(rep.duplicate_faces, 0u);
  EXPECT_EQ(rep.degenerate_faces, 0u);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.oriented);
  const Metrics& m = artifact<Metrics>(r, "metrics");
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
  const AlgorithmResult r = run_algorithm("repair", in);
  const Mesh& out = artifact<Mesh>(r, "mesh");
  EXPECT_EQ(out.num_vertices(), 8u);
  EXPECT_EQ(out.num_faces(), 12u);
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.closed);
  EXPECT_TRUE(rep.oriented);
  EXPECT_EQ(rep.genus, 0);
  ASSERT_TRUE(rep.volume.has_value());
  EXPECT_NEAR(*rep.volume, 1.0, 1e-9);
  const Metrics& m = artifact<Metrics>(r, "metrics");
  EXPECT_EQ(m.at("vertices_merged"), 28);
  EXPECT_EQ(m.at("closed_before"), 0);
  EXPECT_EQ(m.at("closed_after"), 1);
}

TEST(RepairTest, ManifoldInputIsUnchanged) {
  const Mesh in = test::torus();
  const AlgorithmResult r = run_algorithm("repair", in);
  const Mesh& out = artifact<Mesh>(r, "mesh");
  EXPECT_EQ(out.num_vertices(), in.num_vertices());
  EXPECT_EQ(out.num_faces(), in.num_faces());
  const Metrics& m = artifact<Metrics>(r, "metrics");
  EXPECT_EQ(m.at("faces_removed"), 0);
  EXPECT_EQ(m.at("vertices_merged"), 0);
  EXPECT_EQ(m.at("vertices_duplicated"), 0);
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::size_t(q * double(v.size() - 1))];
}

TEST(GeodesicDistanceTest, SphereFromNorthPoleMatchesGreatCircle) {
  const Mesh sphere = test::uv_sphere(1.0, 64, 128);
  const AlgorithmResult r = run_algorithm("geodesic_distance", sphere, {{"sources", std::string("0")}});
  const ScalarField& f = artifact<ScalarField>(r, "distance");
  ASSERT_EQ(f.values.size(), sphere.num_vertices());
  EXPECT_EQ(f.location, Location::vertex);
  EXPECT_EQ(f.hint, ColorHint::magnitude);
  EXPECT_NEAR(f.values[0], 0.0, 1e-3);
  std::vector<double> errors;
  for (std::size_t i = 0; i < sphere.num_vertices(); ++i) {
    const double exact = std::acos(std::clamp(sphere.positions[i].z, -1.0, 1.0));
    if (exact > 0.3) errors.push_back(std::abs(double(f.values[i]) - exact) / exact);
  }
  ASSERT_GT(errors.size(), 1000u);
  EXPECT_LT(percentile(errors, 0.5), 0.05);
  EXPECT_LT(percentile(errors, 0.95), 0.05);
}

TEST(GeodesicDistanceTest, TwoSourcesTakeTheNearer) {
  const Mesh sphere = test::uv_sphere(1.0, 32, 64);
  const Index south = Index(sphere.num_vertices() - 1);
  const AlgorithmResult r = run_algorithm("geodesic_distance", sphere, {{"sources", "0, " + std::to_string(south)}});
  const ScalarField& f = artifact<ScalarField>(r, "distance");
  EXPECT_NEAR(f.values[0], 0.0, 0.02);
  EXPECT_NEAR(f.values[south], 0.0, 0.02);
  // The equator is pi/2 from both poles.
  const float max = f.range().second;
  EXPECT_NEAR(max, std::numbers::pi / 2, 0.1);
}

TEST(GeodesicDistanceTest, BadSourcesAreInvalidInput) {
  const Mesh sphere = test::uv_sphere();
  const std::vector<std::string> bads = {"", "x", "1,", "-1", "3.5", std::to_string(sphere.num_vertices())};
  for (const std::string& bad : bads) {
    try {
      run_algorithm("geodesic_distance", sphere, {{"sources", bad}});
      ADD_FAILURE() << "no error for sources '" << bad << "'";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find("sources"), std::string::npos) << e.what();
    }
  }
}

TEST(GeodesicDistanceTest, NonManifoldInputIsInvalid) {
  try {
    run_algorithm("geodesic_distance", three_on_an_edge());
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("manifold"), std::string::npos) << e.what();
  }
}

AlgorithmResult hausdorff(const Mesh& mesh, const Mesh& reference, const Values& values = {}) {
  Inputs in;
  in.add("mesh", mesh);
  in.add("reference", reference);
  return run_algorithm("hausdorff", in, values);
}

Mesh translated(Mesh m, Vec3 t) {
  for (Vec3& p : m.positions) p = p + t;
  return m;
}

TEST(HausdorffTest, TranslatedBoxIsAtTheTranslation) {
  const Mesh a = test::box();
  const AlgorithmResult r = hausdorff(a, translated(a, {0.3, 0, 0}));
  const Metrics& m = artifact<Metrics>(r, "metrics");
  const double bound = m.at("error_bound");
  EXPECT_NEAR(m.at("hausdorff"), 0.3, bound + 1e-9);
  EXPECT_NEAR(m.at("mesh_to_reference"), 0.3, bound + 1e-9);
  EXPECT_NEAR(m.at("reference_to_mesh"), 0.3, bound + 1e-9);
  // Vertices on x = 0 are 0.3 from the moved box; those on x = 1 lie on it.
  const ScalarField& f = artifact<ScalarField>(r, "distance");
  ASSERT_EQ(f.values.size(), a.num_vertices());
  for (std::size_t i = 0; i < a.num_vertices(); ++i)
    EXPECT_NEAR(f.values[i], a.positions[i].x == 0 ? 0.3 : 0.0, 1e-6) << "vertex " << i;
}

TEST(HausdorffTest, ConcentricSpheresAreTheirRadiusDifferenceApart) {
  const Mesh inner = test::uv_sphere(1.0, 32, 64), outer = test::uv_sphere(1.2, 32, 64);
  const AlgorithmResult r = hausdorff(outer, inner);
  const Metrics& m = artifact<Metrics>(r, "metrics");
  // Faceting moves each surface inward by at most r (1 - cos(pi / 32)) < 0.006.
  EXPECT_NEAR(m.at("hausdorff"), 0.2, 0.006);
  EXPECT_NEAR(m.at("hausdorff_relative"), m.at("hausdorff") / m.at("bbox_diagonal"), 1e-12);
  const ScalarField& f = artifact<ScalarField>(r, "distance");
  const auto [lo, hi] = f.range();
  EXPECT_GT(lo, 0.2 - 1e-6);
  EXPECT_LT(hi, 0.2 + 0.006);
  EXPECT_LE(m.at("vertex_distance_max"), m.at("mesh_to_reference") + m.at("error_bound"));
}

TEST(HausdorffTest, IdenticalMeshesAreAtZero) {
  const Mesh a = test::torus();
  const AlgorithmResult r = hausdorff(a, a);
  const Metrics& m = artifact<Metrics>(r, "metrics");
  EXPECT_LE(m.at("hausdorff"), m.at("error_bound"));
}

TEST(HausdorffTest, MissingOrBadInputsAreInvalid) {
  const Mesh a = test::box();
  Context ctx;
  try {
    find_algorithm("hausdorff").run(a, {}, ctx);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("input 'reference' is missing"), std::string::npos) << e.what();
  }
  try {
    hausdorff(three_on_an_edge(), a);
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("manifold mesh"), std::string::npos) << e.what();
  }
  try {
    hausdorff(a, Mesh{});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("'reference' has no faces"), std::string::npos) << e.what();
  }
  try {
    hausdorff(a, a, {{"error_bound", 0.0}});
    FAIL() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("error_bound"), std::string::npos) << e.what();
  }
}

// A sphere with one more face on one of its edges: three faces on an edge.
Mesh sphere_with_a_fin() {
  Mesh m = test::uv_sphere(1.0, 16, 32);
  const Tri f = m.faces[40];
  m.positions.push_back({3, 3, 3});
  m.faces.push_back({f[0], f[1], Index(m.positions.size() - 1)});
  return m;
}

TEST(RepairFirstTest, HalfedgeFiltersRefuseANonManifoldMeshOrRepairItWhenAsked) {
  const Mesh fin = sphere_with_a_fin();
  ASSERT_FALSE(mesh_report(fin).manifold);
  for (const std::string name : {"simplify", "smooth", "remesh", "fill_holes", "subdivide", "components"}) {
    SCOPED_TRACE(name);
    try {
      run_algorithm(name, fin);
      ADD_FAILURE() << "no error";
    } catch (const InvalidInput& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(name + " needs a manifold mesh"), std::string::npos) << what;
      EXPECT_NE(what.find("set 'repair'"), std::string::npos) << what;
    }
    const AlgorithmResult r = run_algorithm(name, fin, {{"repair", true}});
    ASSERT_FALSE(r.warnings.empty());
    EXPECT_NE(r.warnings[0].find("repaired first"), std::string::npos) << r.warnings[0];
    const Mesh& out = artifact<Mesh>(r, "mesh");
    EXPECT_GT(out.num_faces(), 0u);
    EXPECT_TRUE(mesh_report(out).manifold);
  }
  // A manifold mesh is left as it is: no warning.
  EXPECT_TRUE(run_algorithm("simplify", test::uv_sphere(), {{"repair", true}}).warnings.empty());
}

}  // namespace
}  // namespace cgview
