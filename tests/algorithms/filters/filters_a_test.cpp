// Group A of the everyday filters (normals, curvature, subdivide, components,
// sample_points), run through the registry against known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "filters/curvature.h"
#include "registry/registry.h"
#include "algorithm_support.h"
#include "invalid_input.h"
#include "test_support.h"

namespace cgview {
namespace {

using test::artifact;
using test::run_algorithm;
using test::Values;

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// Every edge has exactly two faces.
bool closed(const Mesh& m) {
  const EdgeTopology t = edge_topology(m);
  for (std::size_t e = 0; e < t.edges.size(); ++e)
    if (t.edge_faces.degree(e) != 2) return false;
  return true;
}

// Three triangles on the edge (0, 1): no halfedge structure can hold them.
Mesh fin() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.faces = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return m;
}

using test::invalid_input_message;

TEST(Curvature, SphereIsOneOverRAndOneOverRSquared) {
  const double r = 2.0;
  const Mesh m = test::uv_sphere(r, 64, 128);
  const AlgorithmResult res = run_algorithm("curvature", m);
  const ScalarField& H = artifact<ScalarField>(res, "mean_curvature");
  const ScalarField& K = artifact<ScalarField>(res, "gaussian_curvature");
  ASSERT_EQ(H.values.size(), m.num_vertices());
  EXPECT_EQ(H.hint, ColorHint::symmetric);
  EXPECT_EQ(K.hint, ColorHint::symmetric);
  std::vector<double> h, k;
  for (std::size_t v = 0; v < m.num_vertices(); ++v)
    if (std::abs(m.positions[v].z) < 0.8 * r) {
      h.push_back(H.values[v]);
      k.push_back(K.values[v]);
    }
  EXPECT_NEAR(median(h), 1 / r, 0.01 / r);  // 5% is required; measured under 0.1%
  EXPECT_NEAR(median(k), 1 / (r * r), 0.01 / (r * r));
}

TEST(Curvature, GaussBonnetOnTorusAndSphere) {
  const Mesh t = test::torus(2.0, 0.5, 48, 24);
  const CurvatureResult ct = vertex_curvatures(t);
  double total = 0, area = 0;
  for (std::size_t v = 0; v < t.num_vertices(); ++v) {
    total += ct.gaussian[v] * ct.area[v];
    area += ct.area[v];
  }
  EXPECT_NEAR(total, 0.0, 1e-9);
  // The mixed areas tile the surface.
  double faces = 0;
  for (double a : face_areas(t)) faces += a;
  EXPECT_NEAR(area, faces, 1e-9 * faces);

  const Mesh s = test::uv_sphere(1.0, 16, 32);
  const CurvatureResult cs = vertex_curvatures(s);
  total = 0;
  for (std::size_t v = 0; v < s.num_vertices(); ++v) total += cs.gaussian[v] * cs.area[v];
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-9);
}

TEST(Curvature, FlatGridIsZeroInside) {
  const Mesh g = test::grid(6);
  const CurvatureResult c = vertex_curvatures(g);
  for (std::size_t v = 0; v < g.num_vertices(); ++v) {
    EXPECT_NEAR(c.mean[v], 0.0, 1e-9);
    const Vec3 p = g.positions[v];
    if (p.x > 0 && p.x < 6 && p.y > 0 && p.y < 6) {
      EXPECT_NEAR(c.gaussian[v], 0.0, 1e-9);
    }
  }
}

TEST(Curvature, NonManifoldAndEmptyInputAreRefused) {
  EXPECT_NE(invalid_input_message([] { run_algorithm("curvature", fin()); }).find("manifold"), std::string::npos);
  Mesh points;
  points.positions = {{0, 0, 0}};
  EXPECT_NE(invalid_input_message([&] { run_algorithm("curvature", points); }).find("no faces"), std::string::npos);
}

TEST(Normals, SphereNormalsPointOutward) {
  const Mesh m = test::uv_sphere(3.0, 16, 32);
  const AlgorithmResult res = run_algorithm("normals", m);
  const Mesh& out = artifact<Mesh>(res, "mesh");
  ASSERT_EQ(out.normals.size(), m.num_vertices());
  EXPECT_TRUE(out.normal_faces.empty());
  EXPECT_EQ(out.faces, m.faces);
  for (std::size_t v = 0; v < m.num_vertices(); ++v) {
    const Vec3 n = to_double(out.normals[v]);
    EXPECT_NEAR(norm(n), 1.0, 1e-5);
    EXPECT_GT(dot(n, m.positions[v] / norm(m.positions[v])), 0.99);
  }
}

TEST(Subdivide, LoopOnBoxQuadruplesFacesAndStaysClosed) {
  const Mesh b = test::box();
  for (int it = 1; it <= 3; ++it) {
    const Mesh out = artifact<Mesh>(
        run_algorithm("subdivide", b, {{"method", std::string("loop")}, {"iterations", (long long)it}}), "mesh");
    EXPECT_EQ(out.num_faces(), b.num_faces() * std::size_t(std::pow(4, it)));
    EXPECT_TRUE(closed(out));
  }
}

TEST(Subdivide, CatmullClarkAndSqrt3) {
  const Mesh b = test::box();
  const Mesh cc = artifact<Mesh>(run_algorithm("subdivide", b, {{"method", std::string("catmull_clark")}}), "mesh");
  EXPECT_EQ(cc.num_faces(), 12u * 3 * 2);
  EXPECT_TRUE(closed(cc));
  const Mesh s3 =
      artifact<Mesh>(run_algorithm("subdivide", b, {{"method", std::string("sqrt3")}, {"iterations", 2LL}}), "mesh");
  EXPECT_EQ(s3.num_faces(), 12u * 9);
  EXPECT_TRUE(closed(s3));
}

TEST(Subdivide, BadInputIsRefused) {
  EXPECT_NE(invalid_input_message([] {
              run_algorithm("subdivide", fin());
            }).find("1 faces could not be placed in a halfedge structure"),
            std::string::npos);
  EXPECT_NE(invalid_input_message([] {
              run_algorithm("subdivide", test::box(), {{"iterations", 6LL}});
            }).find("iterations"),
            std::string::npos);
  const Mesh big = test::uv_sphere(1.0, 200, 400);  // ~160k faces, x4^5 > the limit
  EXPECT_NE(invalid_input_message([&] {
              run_algorithm("subdivide", big, {{"iterations", 5LL}});
            }).find("limit"),
            std::string::npos);
}

TEST(Components, CountKeepLargestAndDropSmall) {
  const Mesh two = test::merged(test::box(), test::box({2, 0, 0}, {3, 1, 1}));
  const AlgorithmResult counted = run_algorithm("components", two, {{"mode", std::string("count")}});
  EXPECT_EQ(artifact<Metrics>(counted, "metrics").at("components"), 2.0);
  EXPECT_EQ(artifact<Metrics>(counted, "metrics").at("kept"), 2.0);
  EXPECT_EQ(artifact<Mesh>(counted, "mesh").num_faces(), 24u);

  const AlgorithmResult largest = run_algorithm("components", two);
  EXPECT_EQ(artifact<Metrics>(largest, "metrics").at("kept"), 1.0);
  EXPECT_EQ(artifact<Mesh>(largest, "mesh").num_faces(), 12u);
  EXPECT_EQ(artifact<Mesh>(largest, "mesh").num_vertices(), 8u);

  const Mesh uneven = test::merged(test::box(), subdivide_midpoint(test::box({2, 0, 0}, {3, 1, 1})));
  const AlgorithmResult dropped =
      run_algorithm("components", uneven, {{"mode", std::string("drop_smaller_than")}, {"min_faces", 20LL}});
  EXPECT_EQ(artifact<Metrics>(dropped, "metrics").at("kept"), 1.0);
  const Mesh& kept = artifact<Mesh>(dropped, "mesh");
  EXPECT_EQ(kept.num_faces(), 48u);
  for (const Vec3& p : kept.positions) EXPECT_GE(p.x, 2.0);
}

TEST(Components, NonManifoldIsRefused) {
  EXPECT_NE(invalid_input_message([] { run_algorithm("components", fin()); }).find("manifold"), std::string::npos);
}

TEST(SamplePoints, CountAndPointsOnTheSurface) {
  const double r = 1.5;
  const Mesh s = test::uv_sphere(r, 16, 32);
  const Mesh pts = artifact<Mesh>(run_algorithm("sample_points", s, {{"count", 2000LL}}), "points");
  ASSERT_EQ(pts.num_vertices(), 2000u);
  EXPECT_EQ(pts.num_faces(), 0u);
  // On the polyhedron, so within the sphere and no deeper than its flattest facet.
  const double inner = r * std::cos(std::numbers::pi / 16);
  for (const Vec3& p : pts.positions) {
    EXPECT_LE(norm(p), r + 1e-9);
    EXPECT_GE(norm(p), inner - 1e-9);
  }
  // On a box every point lies exactly on a face.
  const Mesh onbox = artifact<Mesh>(run_algorithm("sample_points", test::box(), {{"count", 500LL}}), "points");
  ASSERT_EQ(onbox.num_vertices(), 500u);
  for (const Vec3& p : onbox.positions) {
    const double d = std::min({p.x, 1 - p.x, p.y, 1 - p.y, p.z, 1 - p.z});
    EXPECT_NEAR(d, 0.0, 1e-12);
    EXPECT_GE(d, -1e-12);
  }
  // The seed makes it reproducible.
  const Mesh again = artifact<Mesh>(run_algorithm("sample_points", test::box(), {{"count", 500LL}}), "points");
  EXPECT_EQ(again.positions.front(), onbox.positions.front());
  const Mesh other =
      artifact<Mesh>(run_algorithm("sample_points", test::box(), {{"count", 500LL}, {"seed", 7LL}}), "points");
  EXPECT_NE(other.positions.front(), onbox.positions.front());
}

TEST(SamplePoints, NoFacesIsRefused) {
  Mesh points;
  points.positions = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_NE(invalid_input_message([&] { run_algorithm("sample_points", points); }).find("no faces"), std::string::npos);
}

TEST(Normals, NonManifoldFacesAreAWarning) {
  const AlgorithmResult res = run_algorithm("normals", fin());
  ASSERT_EQ(res.warnings.size(), 1u);
  EXPECT_NE(res.warnings[0].find("halfedge structure"), std::string::npos);
  EXPECT_EQ(artifact<Mesh>(res, "mesh").normals.size(), 5u);
}

TEST(Filters, ProgressIsReportedAndCancellationHonoured) {
  for (const char* name : {"normals", "curvature", "subdivide", "components", "sample_points"}) {
    double last = -1;
    Context ctx([&](double f, std::string_view) { last = f; }, [] { return false; });
    find_algorithm(name).run(test::box(), {}, ctx);
    EXPECT_EQ(last, 1.0) << name;
    Context cancelled(nullptr, [] { return true; });
    EXPECT_THROW(find_algorithm(name).run(test::box(), {}, cancelled), Cancelled) << name;
  }
}

TEST(Filters, RegisteredInTheFiltersArea) {
  for (const char* name : {"normals", "curvature", "subdivide", "components", "sample_points"})
    EXPECT_EQ(find_algorithm(name).info.area, "filters") << name;
}

}  // namespace
}  // namespace cgview
