// voxelize: exact counts on boxes, conservative volumes on spheres, no gaps
// on thin, diagonal and tiny triangles, the topology of a torus, analytic
// slices, bad input.
#include "voxel/voxelize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "registry/registry.h"
#include "test_support.h"
#include "voxel/voxel_ops.h"
#include "voxel_samples.h"

namespace cgview {
namespace {

using test::error_of;
using test::mesh_volume;
using test::vox;

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

// ---- point clouds ----------------------------------------------------------------------

// A mesh with no faces, as a point cloud is stored: each point marks the
// voxel [i, i+1) x [j, j+1) x [k, k+1) holding it, a point on the box's far
// side the last voxel before the padding; solid mode has no inside to fill.
TEST(VoxelizeTest, APointCloudMarksTheVoxelsHoldingItsPoints) {
  Mesh cloud;
  cloud.positions = {{0, 0, 0}, {3, 3, 3}, {0.5, 1.0, 2.999}, {2.49, 0.01, 1.5}, {3, 0.25, 0.75}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 3.0);
  for (int n = 0; n < 200; ++n) cloud.positions.push_back({u(rng), u(rng), u(rng)});
  const VoxelizeResult r = voxelize(cloud, {.voxel_size = 0.5, .mode = VoxelizeMode::surface});
  ASSERT_EQ(r.grid.dims(), (std::array<int, 3>{8, 8, 8}));
  std::set<std::array<int, 3>> expected;
  for (const Vec3& q : cloud.positions)
    expected.insert(
        {1 + std::min(5, int(q.x / 0.5)), 1 + std::min(5, int(q.y / 0.5)), 1 + std::min(5, int(q.z / 0.5))});
  std::set<std::array<int, 3>> marked;
  for (std::size_t n = 0; n < r.grid.size(); ++n)
    if (r.grid.bytes()[n]) {
      const auto v = r.grid.unlinear(n);
      marked.insert({v.i, v.j, v.k});
    }
  EXPECT_EQ(marked, expected);
  EXPECT_EQ(r.surface_voxels, expected.size());
  EXPECT_EQ(r.metrics.at("occupied_voxels"), double(expected.size()));
  EXPECT_TRUE(r.warnings.empty());

  const std::string solid = error_of([&] { voxelize(cloud, {.voxel_size = 0.5, .mode = VoxelizeMode::solid}); });
  EXPECT_NE(solid.find("a point cloud (a mesh with no faces) has no inside"), std::string::npos) << solid;
  EXPECT_NE(error_of([&] { vox(Mesh{}, 8, VoxelizeMode::surface); }).find("empty"), std::string::npos);
  Mesh one;
  one.positions = {{1, 2, 3}};
  EXPECT_EQ(voxelize(one, {.voxel_size = 0.1, .mode = VoxelizeMode::surface}).surface_voxels, 1u);

  // As a job runs it.
  Context ctx;
  const AlgorithmResult job =
      find_algorithm("voxelize").run(cloud, {{"voxel_size", 0.5}, {"mode", std::string("surface")}}, ctx);
  EXPECT_EQ(std::get<VoxelGrid>(job.artifacts.at(0).value).count_occupied(), expected.size());
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
  EXPECT_NE(error_of([&] { vox(box, 8, VoxelizeMode::solid, -1); }).find("'padding'"), std::string::npos);
  EXPECT_NE(error_of([&] { vox(Mesh{}, 8, VoxelizeMode::solid); }).find("no faces"), std::string::npos);
  Mesh nan = box;
  nan.positions[0].x = NAN;
  EXPECT_NE(error_of([&] { vox(nan, 8, VoxelizeMode::solid); }), "(no InvalidInput thrown)");

  // Through the registry: the same rules, as parameters.
  const Algorithm& a = find_algorithm("voxelize");
  Context ctx;
  EXPECT_NE(error_of([&] { a.run(box, {{"resolution", 0LL}}, ctx); }).find("resolution"), std::string::npos);
  EXPECT_NE(error_of([&] { a.run(box, {{"mode", std::string("hollow")}}, ctx); }).find("'mode'"), std::string::npos);
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

TEST(VoxelizeTest, GivesGridAndMetrics) {
  const VoxelizeResult r = voxelize(test::box({0, 0, 0}, {2, 3, 4}), {.resolution = 16, .mode = VoxelizeMode::surface});
  EXPECT_EQ(r.grid.count_occupied(), 696u);
  EXPECT_EQ(r.metrics.at("surface_voxels"), 696);
  EXPECT_EQ(r.metrics.at("dim_x"), 10);
  EXPECT_EQ(r.metrics.count("boundary_loops"), 0u);  // solid mode only
}

// Through the registry: the grid first, then the metrics.
TEST(VoxelizeTest, RegisteredAlgorithmNamesItsArtifacts) {
  const Algorithm& a = find_algorithm("voxelize");
  Context ctx;
  const AlgorithmResult r =
      a.run(test::box({0, 0, 0}, {2, 3, 4}), {{"resolution", 16LL}, {"mode", std::string("surface")}}, ctx);
  ASSERT_EQ(r.artifacts.size(), 2u);
  EXPECT_EQ(r.artifacts[0].name, "grid");
  EXPECT_EQ(std::get<VoxelGrid>(r.artifacts[0].value).count_occupied(), 696u);
  EXPECT_EQ(r.artifacts[1].name, "metrics");
  EXPECT_EQ(std::get<Metrics>(r.artifacts[1].value).at("surface_voxels"), 696);
}

// Before a job runs, the server's precheck refuses a grid over the memory
// limit from the stored bounding box alone.
TEST(VoxelizeTest, PrecheckRefusesAGridOverTheLimit) {
  const Algorithm& a = find_algorithm("voxelize");
  ASSERT_TRUE(a.precheck);
  const InputSummaries in{{"mesh", {.bbox = BBox{{0, 0, 0}, {1, 1, 1}}, .vertices = 8, .faces = 12}}};
  EXPECT_NO_THROW(a.precheck(in, {{"resolution", 64LL}}));
  EXPECT_NE(error_of([&] {
              a.precheck(in, {{"resolution", 1000LL}, {"max_memory_mb", 64.0}});
            }).find("over the limit max_memory_mb = 64 MB"),
            std::string::npos);
}

TEST(VoxelizeTest, CancelledJobsThrow) {
  Context ctx({}, [] { return true; });
  EXPECT_THROW(voxelize(test::box(), {.resolution = 8}, &ctx), Cancelled);
}

}  // namespace
}  // namespace cgview
