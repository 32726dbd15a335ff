// .vdb files written by CGView, read back with OpenVDB itself (the library
// that owns the format), and the CLI path `cgview run voxelize ... -o x.vdb`.
#include <openvdb/openvdb.h>

#include <gtest/gtest.h>

#include "test_support.h"
#include "voxel/voxel_io.h"
#include "voxel/voxelize.h"

namespace cgview {
namespace {

openvdb::FloatGrid::Ptr read_with_openvdb(const std::filesystem::path& path) {
  openvdb::initialize();
  openvdb::io::File file(path.string());
  file.open();
  auto base = file.readGrid("density");
  file.close();
  return openvdb::gridPtrCast<openvdb::FloatGrid>(base);
}

TEST(VoxelVdbTest, OpenVdbReadsWhatCGViewWrites) {
  VoxelizeParams p;
  p.resolution = 24;
  const VoxelizeResult r = voxelize(test::torus(2.0, 0.6, 48, 24), p);
  const std::filesystem::path path = test::temp_dir("vdb") / "torus.vdb";
  write_voxel_grid(r.grid, path);
  const auto grid = read_with_openvdb(path);
  ASSERT_TRUE(grid);
  EXPECT_EQ(grid->getGridClass(), openvdb::GRID_FOG_VOLUME);
  EXPECT_EQ(grid->activeVoxelCount(), openvdb::Index64(r.grid.count_occupied()));
  EXPECT_NEAR(grid->voxelSize()[0], r.grid.voxel_size(), 1e-12);
  // Each active voxel sits at the centre of the same voxel of CGView's grid.
  std::size_t checked = 0;
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (auto ci = box.begin(); ci; ++ci, ++checked) {
      const openvdb::Vec3d w = grid->indexToWorld(*ci);
      const VoxelIndex v = r.grid.locate({w[0], w[1], w[2]});
      ASSERT_TRUE(r.grid.occupied(v));
      const Vec3 c = r.grid.center(v);
      ASSERT_NEAR(c.x, w[0], 1e-9);
      ASSERT_NEAR(c.y, w[1], 1e-9);
      ASSERT_NEAR(c.z, w[2], 1e-9);
      ASSERT_EQ(*it, 1.0f);
    }
  }
  EXPECT_EQ(checked, r.grid.count_occupied());
  // And CGView's reader gives the grid back.
  const VoxelGrid back = read_voxel_grid(path);
  EXPECT_EQ(back.dims(), r.grid.dims());
  EXPECT_EQ(back.type(), VoxelType::bit);
  EXPECT_EQ(back.bytes(), r.grid.bytes());
  for (int d = 0; d < 3; ++d) EXPECT_NEAR(back.origin()[d], r.grid.origin()[d], 1e-9);
}

TEST(VoxelVdbTest, FloatGridsKeepTheirValues) {
  VoxelGrid g({4, 5, 6}, {-1, 0, 1}, 0.1, VoxelType::float32);
  g.set({1, 2, 3}, 2.5f);
  g.set({3, 4, 5}, -7.f);
  const std::filesystem::path path = test::temp_dir("vdbf") / "f.vdb";
  write_voxel_grid(g, path);
  const auto grid = read_with_openvdb(path);
  EXPECT_EQ(grid->activeVoxelCount(), 2u);
  EXPECT_EQ(grid->tree().getValue(openvdb::Coord(1, 2, 3)), 2.5f);
  EXPECT_EQ(grid->tree().getValue(openvdb::Coord(3, 4, 5)), -7.f);
  const VoxelGrid back = read_voxel_grid(path);
  EXPECT_EQ(back.floats(), g.floats());
}

TEST(VoxelVdbTest, CliWritesEveryVoxelFormat) {
  const std::filesystem::path dir = test::temp_dir("vdbcli");
  for (const char* e : {"vdb", "binvox", "nrrd", "vti", "raw", "vox"}) {
    std::string out;
    const std::string file = (dir / (std::string("e.") + e)).string();
    const int rc = test::run(test::bin("cgview") + " run voxelize " + test::sample("elephant.off").string() +
                                 " --resolution 64 -o " + file + " 2>&1",
                             &out);
    EXPECT_EQ(rc, 0) << out;
    EXPECT_TRUE(std::filesystem::exists(file)) << out;
  }
  const VoxelGrid g = read_voxel_grid(dir / "e.vdb");
  EXPECT_EQ(std::max({g.dims()[0], g.dims()[1], g.dims()[2]}), 66);
  std::string out;
  EXPECT_NE(test::run(test::bin("cgview") + " run voxelize " + test::sample("elephant.off").string() +
                          " --resolution 64 --mode hollow -o x.vdb 2>&1",
                      &out),
            0);
  EXPECT_NE(out.find("mode"), std::string::npos) << out;
}

}  // namespace
}  // namespace cgview
