// Voxelization: exact counts on boxes, conservative volumes on
// spheres, no gaps on thin, diagonal and tiny triangles, the topology of a
// torus, analytic slices, grid operations, bad input, and the formats read
// back by their published specifications (parsed here, independently of
// voxel_io.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <numbers>
#include <random>
#include <sstream>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "test_support.h"
#include "voxel/voxel_io.h"
#include "voxel/voxel_ops.h"
#include "voxel/voxelize.h"

namespace cgview {
namespace {

double mesh_volume(const Mesh& m) {
  double v = 0;
  for (const Tri& t : m.faces) v += dot(m.positions[t[0]], cross(m.positions[t[1]], m.positions[t[2]])) / 6.0;
  return v;
}

VoxelizeResult vox(const Mesh& m, int res, VoxelizeMode mode, int padding = 1) {
  VoxelizeParams p;
  p.resolution = res;
  p.mode = mode;
  p.padding = padding;
  return voxelize(m, p);
}

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "(no InvalidInput thrown)";
}

// ---- known answers ----------------------------------------------------------------

TEST(VoxelizeTest, AxisAlignedBoxGivesItsExactVoxelCount) {
  // Sides 2, 3, 4 at resolution 16: voxel size 0.25, so 8 x 12 x 16 voxels inside.
  const Mesh box = test::box({0, 0, 0}, {2, 3, 4});
  const VoxelizeResult solid = vox(box, 16, VoxelizeMode::solid);
  EXPECT_EQ(solid.grid.dims(), (std::array<int, 3>{10, 14, 18}));
  EXPECT_DOUBLE_EQ(solid.grid.voxel_size(), 0.25);
  EXPECT_EQ(solid.solid_voxels, 8u * 12u * 16u);
  EXPECT_EQ(solid.grid.count_occupied(), 8u * 12u * 16u);
  const VoxelizeResult surface = vox(box, 16, VoxelizeMode::surface);
  EXPECT_EQ(surface.surface_voxels, 8u * 12u * 16u - 6u * 10u * 14u);
  // Every occupied voxel lies inside the box.
  for (std::size_t n = 0; n < solid.grid.size(); ++n) {
    if (!solid.grid.bytes()[n]) continue;
    const Vec3 c = solid.grid.center(solid.grid.unlinear(n));
    ASSERT_TRUE(c.x > 0 && c.x < 2 && c.y > 0 && c.y < 3 && c.z > 0 && c.z < 4);
  }
  // A box off the voxel boundaries covers every voxel it enters.
  VoxelizeParams p;
  p.voxel_size = 0.5;
  p.padding = 0;
  const VoxelizeResult off = voxelize(test::box({0.1, 0.1, 0.1}, {1.3, 1.3, 1.3}), p);
  EXPECT_EQ(off.grid.dims(), (std::array<int, 3>{3, 3, 3}));
  EXPECT_EQ(off.solid_voxels, 27u);
}

// A grid over a given box (to match another grid voxel for voxel): a 2 x 2
// x 2 box inside a 4 x 4 x 4 one at voxel size 0.5 fills exactly its 4 x 4
// x 4 voxels, where the bigger box puts them; a box that leaves faces out
// is refused.
TEST(VoxelizeTest, AGivenBoxSetsTheGrid) {
  VoxelizeParams p;
  p.voxel_size = 0.5;
  p.box = BBox{{-1, -1, -1}, {3, 3, 3}};
  const VoxelizeResult r = voxelize(test::box({0, 0, 0}, {2, 2, 2}), p);
  EXPECT_EQ(r.grid.dims(), (std::array<int, 3>{10, 10, 10}));
  EXPECT_EQ(r.grid.origin().x, -1.5);
  EXPECT_EQ(r.solid_voxels, 64u);
  for (std::size_t n = 0; n < r.grid.size(); ++n) {
    const Vec3 c = r.grid.center(r.grid.unlinear(n));
    const bool in = c.x > 0 && c.x < 2 && c.y > 0 && c.y < 2 && c.z > 0 && c.z < 2;
    ASSERT_EQ(bool(r.grid.bytes()[n]), in) << c.x << " " << c.y << " " << c.z;
  }
  p.box = BBox{{0.5, 0, 0}, {3, 3, 3}};
  EXPECT_THROW(voxelize(test::box({0, 0, 0}, {2, 2, 2}), p), InvalidInput);
  // A rounding error past the box is no error (a decimated copy's means).
  p.box = BBox{{0, 0, 0}, {2, 2, 2}};
  EXPECT_EQ(voxelize(test::box({0, 0, 0}, {2, 2, std::nextafter(2.0, 3.0)}), p).solid_voxels, 64u);
}

TEST(VoxelizeTest, PaddingStaysEmpty) {
  // refined_elephant's coordinates are not dyadic: rounding must not reach the padding.
  const Mesh m = read_mesh(test::sample("elephant.off"));
  for (int res : {48, 97, 128}) {
    const VoxelizeResult r = vox(m, res, VoxelizeMode::surface, 2);
    const auto d = r.grid.dims();
    for (std::size_t n = 0; n < r.grid.size(); ++n) {
      if (!r.grid.bytes()[n]) continue;
      const VoxelIndex v = r.grid.unlinear(n);
      ASSERT_TRUE(v.i >= 2 && v.j >= 2 && v.k >= 2 && v.i < d[0] - 2 && v.j < d[1] - 2 && v.k < d[2] - 2)
          << "resolution " << res << ": voxel " << v.i << " " << v.j << " " << v.k << " of " << d[0] << "x" << d[1]
          << "x" << d[2];
    }
  }
}

TEST(VoxelizeTest, SphereSolidVolumeIsConservativeAndConverges) {
  const Mesh sphere = test::uv_sphere(1.0, 96, 192);
  const double v_mesh = mesh_volume(sphere);
  double previous_excess = 0;
  for (int res : {64, 128, 256}) {
    const VoxelizeResult r = vox(sphere, res, VoxelizeMode::solid);
    const double s = r.grid.voxel_size();
    const double v = double(r.solid_voxels) * s * s * s;
    EXPECT_GE(v, v_mesh) << "resolution " << res;
    const double excess = v - v_mesh;
    // The excess is a shell about one voxel thick: area * s * (0.5 .. 2).
    EXPECT_GT(excess, 4 * std::numbers::pi * s * 0.5) << "resolution " << res;
    EXPECT_LT(excess, 4 * std::numbers::pi * s * 2.0) << "resolution " << res;
    if (previous_excess > 0) {
      const double ratio = excess / previous_excess;
      EXPECT_GT(ratio, 0.4) << "resolution " << res;
      EXPECT_LT(ratio, 0.6) << "resolution " << res;
    }
    previous_excess = excess;
  }
}

// Points spread over a triangle (none on a voxel boundary, almost surely).
std::vector<Vec3> points_on(const Mesh& m, int per_face, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> out;
  for (const Tri& t : m.faces)
    for (int i = 0; i < per_face; ++i) {
      double a = u(rng), b = u(rng);
      if (a + b > 1) a = 1 - a, b = 1 - b;
      const Vec3 &p = m.positions[t[0]], &q = m.positions[t[1]], &r = m.positions[t[2]];
      out.push_back(p + (q - p) * a + (r - p) * b);
    }
  return out;
}

void expect_covered_and_connected(const Mesh& m, const VoxelizeResult& r, const char* what, int per_face = 200) {
  std::size_t missing = 0;
  for (const Vec3& p : points_on(m, per_face, 7)) missing += !r.grid.occupied(r.grid.locate(p));
  EXPECT_EQ(missing, 0u) << what << ": points of the surface in unmarked voxels";
  std::vector<std::uint32_t> label;
  EXPECT_EQ(r.grid.components(Connectivity::twenty_six, label), 1u) << what;
}

// A plate along a diagonal plane, given as thin slivers meeting at a corner.
Mesh diagonal_plate(int slivers, Vec3 origin, Vec3 e1, Vec3 e2) {
  Mesh m;
  m.positions.push_back(origin);
  for (int i = 0; i <= slivers; ++i) {
    const double t = double(i) / slivers;
    m.positions.push_back(origin + e1 + e2 * t);
  }
  for (int i = 0; i < slivers; ++i) m.faces.push_back({0, Index(i + 1), Index(i + 2)});
  return m;
}

TEST(VoxelizeTest, ThinDiagonalPlateHasNoHolesInSurfaceMode) {
  // 2000 slivers, each far thinner than a voxel, on a plane slanted on all axes.
  const Mesh plate = diagonal_plate(2000, {0, 0, 0}, {1.0, 0.83, 0.61}, {-0.37, 0.71, -0.52});
  for (int res : {16, 64, 200}) {
    const VoxelizeResult r = vox(plate, res, VoxelizeMode::surface);
    expect_covered_and_connected(plate, r, ("sliver plate at " + std::to_string(res)).c_str());
  }
  // Tiny triangles: a sphere whose triangles are far smaller than a voxel.
  const Mesh fine = test::uv_sphere(1.0, 200, 400);
  expect_covered_and_connected(fine, vox(fine, 24, VoxelizeMode::surface), "fine sphere", 4);
  // A closed thin slab (thickness 1/50 of a voxel) turned diagonally, in solid mode.
  Mesh slab = test::box({0, 0, 0}, {1, 1, 0.0005});
  for (Vec3& p : slab.positions)
    p = Vec3{p.x + 0.3 * p.y + 0.4 * p.z, p.y - 0.5 * p.z + 0.2 * p.x, p.z + 0.6 * p.x + 0.3 * p.y};
  const VoxelizeResult r = vox(slab, 40, VoxelizeMode::solid);
  expect_covered_and_connected(slab, r, "thin slab, solid");
}

TEST(VoxelizeTest, TorusSolidHasOneComponentAndOneTunnel) {
  const Mesh torus = test::torus(2.0, 0.6, 64, 32);
  const VoxelizeResult solid = vox(torus, 64, VoxelizeMode::solid);
  const VoxelTopology t = voxel_topology(solid.grid);
  EXPECT_EQ(t.components, 1u);
  EXPECT_EQ(t.cavities, 0u);
  EXPECT_EQ(t.tunnels, 1u);
  EXPECT_EQ(t.euler, 0);
  // Its surface voxels alone: a hollow torus (one cavity, two tunnels).
  const VoxelTopology s = voxel_topology(vox(torus, 64, VoxelizeMode::surface).grid);
  EXPECT_EQ(s.components, 1u);
  EXPECT_EQ(s.cavities, 1u);
  EXPECT_EQ(s.tunnels, 2u);
  // A sphere: a ball.
  const VoxelTopology b = voxel_topology(vox(test::uv_sphere(1, 24, 48), 32, VoxelizeMode::solid).grid);
  EXPECT_EQ(b.components, 1u);
  EXPECT_EQ(b.tunnels, 0u);
  EXPECT_EQ(b.euler, 1);
}

TEST(VoxelizeTest, SlicesMatchAnalyticCrossSections) {
  // Box: every z slice inside it is the 8 x 12 rectangle, the ones outside are empty.
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  for (int k = 0; k < box.grid.dims()[2]; ++k) {
    const VoxelSlice s = slice(box.grid, 2, k);
    ASSERT_EQ(s.width, 10);
    ASSERT_EQ(s.height, 14);
    std::size_t n = 0;
    for (float v : s.values) n += v != 0;
    EXPECT_EQ(n, (k >= 1 && k <= 16) ? 96u : 0u) << "slice " << k;
  }
  const VoxelSlice sx = slice(box.grid, 0, 5);
  EXPECT_EQ(sx.width, 14);
  EXPECT_EQ(sx.height, 18);
  // Sphere of radius 1: slice k covers the slab [z0, z1]; its area lies between the
  // disc of the slab's smallest radius (less the mesh's inscribed chords) and the
  // disc of its largest radius grown by a voxel's diagonal.
  const Mesh sphere = test::uv_sphere(1.0, 96, 192);
  const VoxelizeResult r = vox(sphere, 128, VoxelizeMode::solid);
  const double s = r.grid.voxel_size();
  for (int axis = 0; axis < 3; ++axis)
    for (int k = 4; k < r.grid.dims()[axis] - 4; k += 7) {
      const VoxelSlice sl = slice(r.grid, axis, k);
      std::size_t n = 0;
      for (float v : sl.values) n += v != 0;
      const double area = double(n) * s * s;
      const double z0 = r.grid.origin()[axis] + k * s, z1 = z0 + s;
      const double zmin = (z0 <= 0 && z1 >= 0) ? 0 : std::min(std::abs(z0), std::abs(z1));
      const double zmax = std::max(std::abs(z0), std::abs(z1));
      const double rmax = std::sqrt(std::max(0.0, 1 - zmin * zmin));
      const double rmin = std::sqrt(std::max(0.0, 1 - zmax * zmax)) * std::cos(std::numbers::pi / 96);
      EXPECT_GE(area, std::numbers::pi * std::pow(std::max(0.0, rmin - 0.002), 2)) << "axis " << axis << " slice " << k;
      EXPECT_LE(area, std::numbers::pi * std::pow(rmax + std::sqrt(2.0) * s, 2)) << "axis " << axis << " slice " << k;
    }
}

// ---- bad input ----------------------------------------------------------------------

TEST(VoxelizeTest, BadInputGivesClearErrors) {
  const Mesh box = test::box();
  EXPECT_NE(error_of([&] { vox(box, 0, VoxelizeMode::solid); }).find("'resolution'"), std::string::npos);
  const std::string big = error_of([&] { vox(box, 4000, VoxelizeMode::solid); });
  EXPECT_NE(big.find("4002x4002x4002"), std::string::npos) << big;
  EXPECT_NE(big.find("59.7 GB"), std::string::npos) << big;
  EXPECT_NE(big.find("max_memory_mb = 2048"), std::string::npos) << big;
  VoxelizeParams p;
  p.resolution = 200;
  p.max_memory_mb = 1;
  EXPECT_NE(error_of([&] { voxelize(box, p); }).find("7.9 MB"), std::string::npos);
  EXPECT_NE(error_of([&] { parse_voxelize_mode("hollow"); }).find("'mode'"), std::string::npos);
  EXPECT_NE(error_of([&] { vox(box, 8, VoxelizeMode::solid, -1); }).find("'padding'"), std::string::npos);
  EXPECT_NE(error_of([&] { vox(Mesh{}, 8, VoxelizeMode::solid); }).find("no faces"), std::string::npos);
  Mesh nan = box;
  nan.positions[0].x = NAN;
  EXPECT_NE(error_of([&] { vox(nan, 8, VoxelizeMode::solid); }), "(no InvalidInput thrown)");
  const VoxelizeResult r = vox(box, 8, VoxelizeMode::solid);
  EXPECT_NE(error_of([&] {
              slice(r.grid, 2, 10);
            }).find("slice index 10 is out of range: the grid has 10 voxels along z (0..9)"),
            std::string::npos);
  EXPECT_NE(error_of([&] { slice(r.grid, 2, -1); }).find("out of range"), std::string::npos);
  EXPECT_NE(error_of([&] { slice(r.grid, 3, 0); }).find("axis"), std::string::npos);

  // Through the registry: the same rules, as parameters.
  const Algorithm& a = find_algorithm("voxelize");
  Context ctx;
  EXPECT_NE(error_of([&] { a.run(box, {{"resolution", 0LL}}, ctx); }).find("resolution"), std::string::npos);
  EXPECT_NE(error_of([&] { a.run(box, {{"mode", std::string("hollow")}}, ctx); }).find("mode"), std::string::npos);
  EXPECT_NE(error_of([&] {
              a.run(box, {{"resolution", 8000LL}, {"max_memory_mb", 100.0}}, ctx);
            }).find("GB"),
            std::string::npos);
}

TEST(VoxelizeTest, OpenMeshGetsAWarningWithItsBoundaryLoops) {
  const Mesh open = test::grid(4);
  const VoxelizeResult r = vox(open, 16, VoxelizeMode::solid);
  EXPECT_EQ(r.boundary_loops, 1u);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].find("1 boundary loop"), std::string::npos) << r.warnings[0];
  EXPECT_EQ(r.solid_voxels, r.surface_voxels);  // a flat sheet encloses nothing
  // A box with half a side removed: one loop, a hole wider than a voxel lets the outside in.
  Mesh cut = test::box();
  cut.faces.pop_back();
  const VoxelizeResult c = vox(cut, 8, VoxelizeMode::solid);
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.solid_voxels, c.surface_voxels);
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("nothing was enclosed"), std::string::npos);
  // The same hole at a resolution of 2: narrower than a voxel, so the solid is whole.
  EXPECT_EQ(vox(cut, 2, VoxelizeMode::solid).solid_voxels, 8u);
  EXPECT_TRUE(vox(test::box(), 8, VoxelizeMode::solid).warnings.empty());
}

TEST(VoxelizeTest, RegisteredAlgorithmGivesGridAndMetrics) {
  const Algorithm& a = find_algorithm("voxelize");
  Context ctx;
  const AlgorithmResult r =
      a.run(test::box({0, 0, 0}, {2, 3, 4}), {{"resolution", 16LL}, {"mode", std::string("surface")}}, ctx);
  ASSERT_EQ(r.artifacts.size(), 2u);
  EXPECT_EQ(r.artifacts[0].name, "grid");
  const VoxelGrid& g = std::get<VoxelGrid>(r.artifacts[0].value);
  EXPECT_EQ(g.count_occupied(), 696u);
  const Metrics& m = std::get<Metrics>(r.artifacts[1].value);
  EXPECT_EQ(m.at("surface_voxels"), 696);
  EXPECT_EQ(m.at("dim_x"), 10);
}

TEST(VoxelizeTest, VoxelSurfaceAlgorithmGivesTheMergedBoundary) {
  const Algorithm& a = find_algorithm("voxel_surface");
  Context ctx;
  const AlgorithmResult r = a.run(test::box({0, 0, 0}, {2, 3, 4}), {{"resolution", 16LL}}, ctx);
  const Mesh& m = std::get<Mesh>(r.artifacts.at(0).value);
  EXPECT_EQ(m.num_faces(), 12u);
  EXPECT_NEAR(mesh_volume(m), 24.0, 1e-9);
  EXPECT_EQ(std::get<Metrics>(r.artifacts.at(1).value).at("voxels"), 1536);
}

TEST(VoxelizeTest, VoxelDistanceAlgorithmGivesAScalarGrid) {
  const Algorithm& a = find_algorithm("voxel_distance");
  Context ctx;
  const AlgorithmResult r = a.run(test::box({0, 0, 0}, {2, 3, 4}), {{"resolution", 16LL}}, ctx);
  const VoxelGrid& g = std::get<VoxelGrid>(r.artifacts.at(0).value);
  EXPECT_EQ(g.type(), VoxelType::float32);
  EXPECT_FLOAT_EQ(g.get({4, 7, 9}), 1.0f);
  EXPECT_FLOAT_EQ(float(std::get<Metrics>(r.artifacts.at(1).value).at("max_distance")), 1.0f);
  // Its memory limit counts the distances too.
  EXPECT_NE(error_of([&] {
              a.run(test::box(), {{"resolution", 1000LL}}, ctx);
            }).find("13 bytes per voxel"),
            std::string::npos);
}

// ---- grid operations ------------------------------------------------------------------

TEST(VoxelOpsTest, SimplePoints) {
  VoxelGrid g({7, 7, 7}, {0, 0, 0}, 1.0);
  g.set({3, 3, 3}, 1);
  EXPECT_FALSE(is_simple(g, {3, 3, 3}));  // isolated: removing it deletes a component
  g.set({4, 3, 3}, 1);
  g.set({5, 3, 3}, 1);
  EXPECT_TRUE(is_simple(g, {3, 3, 3}));   // end of a line
  EXPECT_FALSE(is_simple(g, {4, 3, 3}));  // middle: removing it splits the line
  EXPECT_FALSE(is_simple(g, {0, 0, 0}));  // empty
  VoxelGrid cube({5, 5, 5}, {0, 0, 0}, 1.0);
  for (int k = 1; k < 4; ++k)
    for (int j = 1; j < 4; ++j)
      for (int i = 1; i < 4; ++i) cube.set({i, j, k}, 1);
  EXPECT_FALSE(is_simple(cube, {2, 2, 2}));  // centre: removing it makes a cavity
  EXPECT_TRUE(is_simple(cube, {1, 1, 1}));   // corner
  EXPECT_TRUE(is_simple(cube, {2, 1, 1}));   // edge
  EXPECT_TRUE(is_simple(cube, {2, 2, 1}));   // face
  // A ring of 8 voxels around a hole: removing any one opens the tunnel.
  VoxelGrid ring({5, 5, 3}, {0, 0, 0}, 1.0);
  for (int j = 1; j < 4; ++j)
    for (int i = 1; i < 4; ++i)
      if (i != 2 || j != 2) ring.set({i, j, 1}, 1);
  EXPECT_FALSE(is_simple(ring, {2, 1, 1}));
  // A corner: its two neighbours on the ring touch by an edge, 26-adjacent, so the ring stays closed.
  EXPECT_TRUE(is_simple(ring, {1, 1, 1}));
}

TEST(VoxelOpsTest, DistanceTransformIsEuclidean) {
  VoxelGrid g({20, 20, 20}, {0, 0, 0}, 0.5);
  g.set({2, 3, 4}, 1);
  const VoxelGrid d = distance_transform(g, {.inside = false});
  EXPECT_EQ(d.type(), VoxelType::float32);
  EXPECT_FLOAT_EQ(d.get({2, 3, 4}), 0.f);
  EXPECT_FLOAT_EQ(d.get({5, 7, 4}), 2.5f);  // (3, 4, 0) voxels: 5 * 0.5
  EXPECT_FLOAT_EQ(d.get({19, 19, 19}), float(0.5 * std::sqrt(17.0 * 17 + 16 * 16 + 15 * 15)));
  // Inside a solid box: the distance to the nearest empty voxel.
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const VoxelGrid in = distance_transform(box.grid);
  EXPECT_FLOAT_EQ(in.get({0, 0, 0}), 0.f);
  EXPECT_FLOAT_EQ(in.get({1, 1, 1}), 0.25f);
  EXPECT_FLOAT_EQ(in.get({4, 7, 9}), 1.0f);  // 4 voxels from the x = 0 side
  // Brute force on a small random grid.
  VoxelGrid rnd({9, 8, 7}, {0, 0, 0}, 1.0);
  std::mt19937 rng(3);
  for (auto& b : rnd.bytes()) b = rng() % 5 == 0;
  const VoxelGrid dr = distance_transform(rnd, {.inside = false});
  for (std::size_t n = 0; n < rnd.size(); ++n) {
    double best = HUGE_VAL;
    const VoxelIndex v = rnd.unlinear(n);
    for (std::size_t m = 0; m < rnd.size(); ++m)
      if (rnd.bytes()[m]) {
        const VoxelIndex w = rnd.unlinear(m);
        best = std::min(
            best, std::sqrt(double((v.i - w.i) * (v.i - w.i) + (v.j - w.j) * (v.j - w.j) + (v.k - w.k) * (v.k - w.k))));
      }
    ASSERT_FLOAT_EQ(dr.floats()[n], float(best)) << n;
  }
}

TEST(VoxelOpsTest, ScalarGridThresholds) {
  // The distance inside a solid box, thresholded: the voxels deeper than 0.5.
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const VoxelGrid depth = distance_transform(box.grid);
  const auto [lo, hi] = value_range(depth);
  EXPECT_EQ(lo, 0.f);
  EXPECT_FLOAT_EQ(hi, 1.0f);  // half the shortest side
  const VoxelGrid deep = threshold(depth, 0.5f);
  EXPECT_EQ(deep.type(), VoxelType::bit);
  // Depth d > 0.5 means more than 2 voxels in from every side: (8-4) x (12-4) x (16-4).
  EXPECT_EQ(deep.count_occupied(), 4u * 8u * 12u);
  EXPECT_EQ(threshold(depth, hi).count_occupied(), 0u);
  EXPECT_EQ(threshold(depth, -1.f).count_occupied(), depth.size());
}

TEST(VoxelOpsTest, BoundaryMeshMergesCoplanarFaces) {
  const VoxelizeResult box = vox(test::box({0, 0, 0}, {2, 3, 4}), 16, VoxelizeMode::solid);
  const Mesh m = boundary_mesh(box.grid);
  EXPECT_EQ(m.num_faces(), 12u);  // six rectangles
  EXPECT_EQ(m.num_vertices(), 8u);
  EXPECT_NEAR(mesh_volume(m), 24.0, 1e-9);  // outward: positive
  const VoxelizeResult sphere = vox(test::uv_sphere(1.0, 32, 64), 32, VoxelizeMode::solid);
  const Mesh ms = boundary_mesh(sphere.grid);
  const double s = sphere.grid.voxel_size();
  EXPECT_NEAR(mesh_volume(ms), double(sphere.solid_voxels) * s * s * s, 1e-9);
  // Merged: far fewer triangles than the 2 per exposed voxel face.
  std::size_t exposed = 0;
  for (std::size_t n = 0; n < sphere.grid.size(); ++n) {
    const VoxelIndex v = sphere.grid.unlinear(n);
    if (!sphere.grid.occupied(v)) continue;
    for (const VoxelIndex& o : VoxelGrid::offsets(Connectivity::six))
      exposed += !sphere.grid.occupied({v.i + o.i, v.j + o.j, v.k + o.k});
  }
  EXPECT_LT(ms.num_faces(), exposed);
}

// ---- formats, read back by their specifications ------------------------------------------

VoxelGrid sample_grid(VoxelType t = VoxelType::bit) {
  // A non-cubic grid with a recognisable pattern.
  VoxelGrid g({5, 7, 3}, {0.5, -1.25, 2.0}, 0.25, t);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 7; ++j)
      for (int i = 0; i < 5; ++i)
        if ((i + 2 * j + 3 * k) % 4 == 0 || (i == 4 && j == 6 && k == 2))
          g.set({i, j, k}, t == VoxelType::float32 ? 0.5f + i : float(1 + i));
  return g;
}

void expect_same(const VoxelGrid& a, const VoxelGrid& b, bool geometry = true) {
  ASSERT_EQ(a.dims(), b.dims());
  if (geometry) {
    EXPECT_NEAR(a.voxel_size(), b.voxel_size(), 1e-12);
    for (int d = 0; d < 3; ++d) EXPECT_NEAR(a.origin()[d], b.origin()[d], 1e-12);
  }
  for (std::size_t n = 0; n < a.size(); ++n) ASSERT_EQ(a.get(a.unlinear(n)), b.get(b.unlinear(n))) << n;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(VoxelFormatsTest, BinvoxBySpecification) {
  const VoxelGrid g = sample_grid();
  const std::filesystem::path path = test::temp_dir("binvox") / "g.binvox";
  write_voxel_grid(g, path);
  const std::string b = slurp(path);
  // Header lines, then (value, count) byte pairs; y fastest, then z, then x.
  std::istringstream in(b);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "#binvox 1");
  int d0, d1, d2;
  double tx, ty, tz, scale;
  std::string key;
  in >> key >> d0 >> d1 >> d2;
  EXPECT_EQ(key, "dim");
  in >> key >> tx >> ty >> tz;
  EXPECT_EQ(key, "translate");
  in >> key >> scale;
  EXPECT_EQ(key, "scale");
  in >> key;
  EXPECT_EQ(key, "data");
  in.get();
  EXPECT_EQ(d0, 7);  // cubic: padded to the largest side
  EXPECT_EQ(d1, 7);
  EXPECT_EQ(d2, 7);
  EXPECT_DOUBLE_EQ(tx, 0.5);
  EXPECT_DOUBLE_EQ(ty, -1.25);
  EXPECT_DOUBLE_EQ(scale, 7 * 0.25);
  std::vector<std::uint8_t> voxels;
  for (;;) {
    const int v = in.get(), c = in.get();
    if (c == EOF) break;
    ASSERT_TRUE(v == 0 || v == 1);
    ASSERT_GE(c, 1);
    voxels.insert(voxels.end(), std::size_t(c), std::uint8_t(v));
  }
  ASSERT_EQ(voxels.size(), 343u);
  for (int x = 0; x < 7; ++x)
    for (int z = 0; z < 7; ++z)
      for (int y = 0; y < 7; ++y)
        EXPECT_EQ(voxels[std::size_t(y + 7 * z + 49 * x)], g.occupied({x, y, z}) ? 1 : 0) << x << y << z;
  const VoxelGrid back = read_voxel_grid(path);
  EXPECT_EQ(back.dims(), (std::array<int, 3>{7, 7, 7}));
  for (int z = 0; z < 3; ++z)
    for (int y = 0; y < 7; ++y)
      for (int x = 0; x < 5; ++x) EXPECT_EQ(back.occupied({x, y, z}), g.occupied({x, y, z}));
  EXPECT_EQ(back.count_occupied(), g.count_occupied());
}

TEST(VoxelFormatsTest, NrrdBySpecification) {
  for (VoxelType t : {VoxelType::bit, VoxelType::uint8, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("nrrd") / "g.nrrd";
    write_voxel_grid(g, path);
    const std::string b = slurp(path);
    ASSERT_EQ(b.compare(0, 8, "NRRD0004"), 0);
    const std::size_t end = b.find("\n\n");
    ASSERT_NE(end, std::string::npos);
    const std::string head = b.substr(0, end + 1);
    EXPECT_NE(head.find(t == VoxelType::float32 ? "\ntype: float\n" : "\ntype: uint8\n"), std::string::npos) << head;
    EXPECT_NE(head.find("\nsizes: 5 7 3\n"), std::string::npos);
    EXPECT_NE(head.find("\nspace directions: (0.25,0,0) (0,0.25,0) (0,0,0.25)\n"), std::string::npos) << head;
    EXPECT_NE(head.find("\nspace origin: (0.625,-1.125,2.125)\n"), std::string::npos) << head;  // voxel 0's centre
    EXPECT_NE(head.find("\nencoding: raw\n"), std::string::npos);
    const std::string data = b.substr(end + 2);
    const std::size_t bpv = t == VoxelType::float32 ? 4 : 1;
    ASSERT_EQ(data.size(), g.size() * bpv);
    for (std::size_t n = 0; n < g.size(); ++n) {
      if (t == VoxelType::float32) {
        float f;
        std::memcpy(&f, data.data() + 4 * n, 4);
        EXPECT_EQ(f, g.floats()[n]);
      } else {
        EXPECT_EQ(std::uint8_t(data[n]), g.bytes()[n]);
      }
    }
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, VtiBySpecification) {
  for (VoxelType t : {VoxelType::uint8, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("vti") / "g.vti";
    write_voxel_grid(g, path);
    const std::string b = slurp(path);
    EXPECT_NE(b.find("<VTKFile type=\"ImageData\""), std::string::npos);
    EXPECT_NE(b.find("header_type=\"UInt64\""), std::string::npos);
    EXPECT_NE(b.find("WholeExtent=\"0 5 0 7 0 3\""), std::string::npos);  // cells: one per voxel
    EXPECT_NE(b.find("Origin=\"0.5 -1.25 2\""), std::string::npos);
    EXPECT_NE(b.find("Spacing=\"0.25 0.25 0.25\""), std::string::npos);
    EXPECT_NE(b.find(t == VoxelType::float32 ? "type=\"Float32\"" : "type=\"UInt8\""), std::string::npos);
    const std::size_t u = b.find('_', b.find("<AppendedData"));
    std::uint64_t n;
    std::memcpy(&n, b.data() + u + 1, 8);
    const std::size_t bpv = t == VoxelType::float32 ? 4 : 1;
    ASSERT_EQ(n, g.size() * bpv);
    const std::string ours(reinterpret_cast<const char*>(t == VoxelType::float32 ? (const void*)g.floats().data()
                                                                                 : (const void*)g.bytes().data()),
                           n);
    EXPECT_EQ(b.substr(u + 9, n), ours);
    EXPECT_NE(b.find("</VTKFile>", u + 9 + n), std::string::npos);
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, MagicaVoxelBySpecification) {
  const VoxelGrid g = sample_grid(VoxelType::uint8);
  const std::filesystem::path path = test::temp_dir("vox") / "g.vox";
  write_voxel_grid(g, path);
  const std::string b = slurp(path);
  auto i32 = [&](std::size_t at) {
    std::int32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;
  };
  ASSERT_EQ(b.substr(0, 4), "VOX ");
  EXPECT_EQ(i32(4), 150);
  ASSERT_EQ(b.substr(8, 4), "MAIN");
  EXPECT_EQ(i32(12), 0);
  EXPECT_EQ(std::size_t(i32(16)), b.size() - 20);
  ASSERT_EQ(b.substr(20, 4), "SIZE");
  EXPECT_EQ(i32(24), 12);
  EXPECT_EQ(i32(32), 5);
  EXPECT_EQ(i32(36), 7);
  EXPECT_EQ(i32(40), 3);
  ASSERT_EQ(b.substr(44, 4), "XYZI");
  const int count = i32(56);
  EXPECT_EQ(std::size_t(count), g.count_occupied());
  EXPECT_EQ(i32(48), 4 + 4 * count);
  for (int v = 0; v < count; ++v) {
    const auto* p = reinterpret_cast<const std::uint8_t*>(b.data() + 60 + 4 * v);
    EXPECT_EQ(float(p[3]), g.get({p[0], p[1], p[2]}));
  }
  const std::size_t pal = 60 + 4 * std::size_t(count);
  EXPECT_EQ(b.substr(pal, 4), "RGBA");
  EXPECT_EQ(i32(pal + 4), 1024);
  expect_same(g, read_voxel_grid(path), false);  // .vox has no origin or voxel size
  // Over 256 per side: a clear error.
  EXPECT_NE(error_of([] {
              write_voxel_grid(VoxelGrid({300, 2, 2}, {0, 0, 0}, 1), test::temp_dir("vox2") / "x.vox");
            }).find("at most 256"),
            std::string::npos);
}

TEST(VoxelFormatsTest, RawWithJsonSidecar) {
  for (VoxelType t : {VoxelType::bit, VoxelType::float32}) {
    const VoxelGrid g = sample_grid(t);
    const std::filesystem::path path = test::temp_dir("raw") / "g.raw";
    write_voxel_grid(g, path);
    const nlohmann::json j = nlohmann::json::parse(slurp(path.string() + ".json"));
    EXPECT_EQ(j["dims"], nlohmann::json({5, 7, 3}));
    EXPECT_EQ(j["voxel_size"], 0.25);
    EXPECT_EQ(j["origin"], nlohmann::json({0.5, -1.25, 2.0}));
    EXPECT_EQ(j["data_file"], "g.raw");
    EXPECT_EQ(j["type"], t == VoxelType::bit ? "bit" : "float32");
    EXPECT_EQ(slurp(path).size(), g.size() * (t == VoxelType::float32 ? 4 : 1));
    expect_same(g, read_voxel_grid(path));
  }
}

TEST(VoxelFormatsTest, BadFilesAreParseErrors) {
  EXPECT_THROW(decode_binvox("#binvox 1\ndim 1000 1000 1000\ndata\n\x01\xff"), ParseError);
  EXPECT_THROW(decode_binvox("hello"), ParseError);
  EXPECT_THROW(decode_nrrd("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 100 100 100\nencoding: raw\n\nxx"), ParseError);
  EXPECT_THROW(decode_vox("VOX "), ParseError);
  std::string vox = encode_vox(sample_grid());
  vox[56] = char(0xff);  // XYZI count far beyond the chunk
  EXPECT_THROW(decode_vox(vox), ParseError);
  EXPECT_THROW(decode_vti("<VTKFile type=\"PolyData\">"), ParseError);
  EXPECT_THROW(read_voxel_grid("x.unknown"), UnsupportedFormat);
  // A bit grid's claim is checked too (fuzz_voxel: a 200-byte NRRD of type
  // bit claimed 4 GB of voxels and got them allocated).
  try {
    (void)decode_nrrd(
        "NRRD0004\ntype: uint8\ncgview_type: bit\ndimension: 3\nsizes: 1000 1000 1000\nencoding: raw\n\nxx");
    ADD_FAILURE() << "a claim of 10^9 voxels in 2 bytes was read";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("the header claims 1000x1000x1000 voxels, more than the file holds"),
              std::string::npos)
        << e.what();
  }
  // Sizes that no integer holds, or not whole (fuzz_voxel found the first:
  // converting 1e100 to an integer is undefined): refused, naming the size.
  for (const std::string size : {"1e100", "nan", "-inf", "2.5", "0"}) {
    try {
      (void)decode_nrrd("NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 " + size + " 2\nencoding: raw\n\nxxxxxxxx");
      ADD_FAILURE() << size << " was read";
    } catch (const ParseError& e) {
      const std::string what = e.what();  // nan and -inf are not numbers to the header's reader
      EXPECT_TRUE(what.find("bad grid dimension") != std::string::npos ||
                  what.find("'sizes' needs 3 numbers") != std::string::npos)
          << what;
    }
    const std::string vti = "<VTKFile type=\"ImageData\"><ImageData WholeExtent=\"0 1 0 " + size +
                            " 0 1\" Origin=\"0 0 0\" Spacing=\"1 1 1\"><Piece><PointData><DataArray type=\"UInt8\" "
                            "format=\"ascii\">0 0 0 0 0 0 0 0</DataArray></PointData></Piece></ImageData></VTKFile>";
    EXPECT_THROW(decode_vti(vti), ParseError) << size;
  }
}

TEST(VoxelFormatsTest, ArtifactWriterTakesEveryVoxelExtension) {
  const Artifact a{"grid", sample_grid()};
  const std::filesystem::path dir = test::temp_dir("artifact");
  for (const char* e : {".binvox", ".raw", ".nrrd", ".vti", ".vox", ".vdb", ".vtk"}) {
    EXPECT_NO_THROW(check_artifact_extension(OutputKind::voxel_grid, std::string("g") + e)) << e;
    write_artifact(a, Mesh{}, dir / (std::string("g") + e));
    EXPECT_TRUE(std::filesystem::exists(dir / (std::string("g") + e))) << e;
  }
  EXPECT_THROW(check_artifact_extension(OutputKind::voxel_grid, "g.png"), UnsupportedFormat);
}

}  // namespace
}  // namespace cgview
