// Everyday filters on CGAL, group B: simplify, remesh, fill_holes,
// run through the registry on shapes with known answers.
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/distance.h>

#include <cmath>
#include <map>
#include <random>
#include <string>

#include "core/mesh_report.h"
#include "core/surface_mesh.h"
#include "io/mesh_io.h"
#include "registry/registry.h"
#include "algorithm_support.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::artifact;
using test::run_algorithm;
using test::Values;

const Mesh& mesh_of(const AlgorithmResult& r) {
  for (const Artifact& a : r.artifacts)
    if (a.name == "mesh") return std::get<Mesh>(a.value);
  throw std::runtime_error("no mesh artifact");
}

double mean_edge_length(const Mesh& m) {
  const EdgeTopology t = edge_topology(m);
  double sum = 0;
  for (const auto& e : t.edges) sum += norm(m.positions[e[0]] - m.positions[e[1]]);
  return sum / double(t.edges.size());
}

double radius_variance(const Mesh& m) {
  double sum = 0, sum2 = 0;
  for (const Vec3& p : m.positions) {
    sum += norm(p);
    sum2 += norm(p) * norm(p);
  }
  const double n = double(m.num_vertices()), mean = sum / n;
  return sum2 / n - mean * mean;
}

Mesh noisy_sphere() {
  Mesh m = test::uv_sphere(1.0, 24, 48);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> noise(-0.03, 0.03);
  for (Vec3& p : m.positions) p = p * (1.0 + noise(rng));
  return m;
}

// Three triangles on one edge: no halfedge structure holds them.
Mesh non_manifold() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

TEST(SimplifyTest, SphereToTargetFacesStaysClose) {
  const double r = 1.0;
  const Mesh sphere = test::uv_sphere(r, 64, 128);
  const int target = 500;
  const Mesh out = mesh_of(run_algorithm("simplify", sphere, {{"target_faces", (long long)target}}));
  EXPECT_LE(out.num_faces(), std::size_t(target));
  EXPECT_GT(out.num_faces(), std::size_t(target) * 9 / 10);
  const MeshReport rep = mesh_report(out);
  EXPECT_TRUE(rep.closed);
  EXPECT_EQ(rep.genus, 0);
  for (const Vec3& p : out.positions) EXPECT_LT(std::abs(norm(p) - r), 0.02 * r);
  const SurfaceMesh a = to_surface_mesh(out).mesh, b = to_surface_mesh(sphere).mesh;
  const double h = CGAL::Polygon_mesh_processing::approximate_symmetric_Hausdorff_distance<CGAL::Sequential_tag>(
      a, b, CGAL::parameters::number_of_points_per_area_unit(4000),
      CGAL::parameters::number_of_points_per_area_unit(4000));
  EXPECT_LT(h, 0.02 * r);
}

TEST(SimplifyTest, RatioHalvesFaces) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const Mesh out = mesh_of(run_algorithm("simplify", sphere, {{"ratio", 0.5}}));
  EXPECT_LE(out.num_faces(), sphere.num_faces() / 2);
  EXPECT_TRUE(mesh_report(out).closed);
}

TEST(RemeshTest, ReachesTargetEdgeLength) {
  const Mesh sphere = test::uv_sphere(1.0, 24, 48);
  const double target = 0.1;
  const Mesh out = mesh_of(run_algorithm("remesh", sphere, {{"target_edge_length", target}, {"iterations", 3LL}}));
  EXPECT_NEAR(mean_edge_length(out), target, 0.2 * target);
  EXPECT_TRUE(mesh_report(out).closed);
}

TEST(RemeshTest, ZeroMeansInputMeanEdgeLength) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  const double before = mean_edge_length(sphere);
  const Mesh out = mesh_of(run_algorithm("remesh", sphere));
  EXPECT_NEAR(mean_edge_length(out), before, 0.2 * before);
}

TEST(FillHolesTest, ClosesTheElephant) {
  const Mesh holed = read_mesh(test::sample("elephant-with-holes.off"));
  const Mesh whole = read_mesh(test::sample("elephant.off"));
  ASSERT_GT(mesh_report(holed).boundary_loops, 0u);
  const AlgorithmResult r = run_algorithm("fill_holes", holed);
  const MeshReport rep = mesh_report(mesh_of(r));
  EXPECT_EQ(rep.boundary_loops, 0u);
  EXPECT_EQ(rep.genus, mesh_report(whole).genus);
  const Metrics& m = std::get<Metrics>(r.artifacts.at(1).value);
  EXPECT_EQ(m.at("holes_found"), double(mesh_report(holed).boundary_loops));
  EXPECT_EQ(m.at("holes_filled"), m.at("holes_found"));
}

TEST(FillHolesTest, TriangulateModeAndSizeLimit) {
  const Mesh g = test::grid(4);  // one hole of 16 edges: the grid's border
  const MeshReport filled =
      mesh_report(mesh_of(run_algorithm("fill_holes", g, {{"mode", std::string("triangulate")}})));
  EXPECT_EQ(filled.boundary_loops, 0u);
  const AlgorithmResult r = run_algorithm("fill_holes", g, {{"max_hole_edges", 10LL}});
  EXPECT_EQ(mesh_report(mesh_of(r)).boundary_loops, 1u);
  EXPECT_EQ(std::get<Metrics>(r.artifacts.at(1).value).at("holes_filled"), 0.0);
  EXPECT_EQ(r.warnings.size(), 1u);
}

TEST(FiltersBTest, NonManifoldInputIsRefused) {
  for (const char* name : {"simplify", "remesh", "fill_holes"}) {
    try {
      run_algorithm(name, non_manifold());
      ADD_FAILURE() << name << " accepted a non-manifold mesh";
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(name) + " needs a manifold mesh"), std::string::npos)
          << e.what();
    }
  }
}

TEST(FiltersBTest, CancelledJobsThrow) {
  const Mesh sphere = test::uv_sphere(1.0, 16, 32);
  for (const char* name : {"simplify", "remesh"}) {
    Context ctx({}, [] { return true; });
    EXPECT_THROW(find_algorithm(name).run(sphere, {}, ctx), Cancelled) << name;
  }
}

TEST(FiltersBTest, ProgressEndsAtOne) {
  double last = -1;
  Context ctx([&](double f, std::string_view) { last = f; }, {});
  find_algorithm("simplify").run(test::uv_sphere(1.0, 16, 32), {{"target_faces", 100LL}}, ctx);
  EXPECT_EQ(last, 1.0);
}

}  // namespace
}  // namespace cgview
