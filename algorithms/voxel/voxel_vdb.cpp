// OpenVDB .vdb files, kept in this one file: OpenVDB's headers are heavy.
//
// Written as a FloatGrid named "density" (what Blender, Houdini and
// ParaView's VDB readers look for first), class fog volume, with the
// occupied voxels active: value 1 for a bit grid, the value for uint8 and
// float grids.  Index (i, j, k) is voxel (i, j, k); the linear transform
// maps it to the voxel's centre (OpenVDB's voxels are centred on integer
// index points).  The grid's dims, origin and type ride in the metadata so
// that a read gives back the same grid; without them (a file from another
// tool), the grid is the active voxels' bounding box.
#include <openvdb/openvdb.h>

#include <cmath>

#include "core/errors.h"
#include "voxel/voxel_io.h"

namespace cgview {

namespace {
void init_once() {
  static const bool done = [] {
    openvdb::initialize();
    return true;
  }();
  (void)done;
}
}  // namespace

void write_vdb(const VoxelGrid& g, const std::filesystem::path& path) {
  init_once();
  auto grid = openvdb::FloatGrid::create(0.f);
  grid->setName("density");
  grid->setGridClass(openvdb::GRID_FOG_VOLUME);
  const double s = g.voxel_size();
  const Vec3 c = g.origin() + Vec3{0.5, 0.5, 0.5} * s;
  auto xf = openvdb::math::Transform::createLinearTransform(s);
  xf->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
  grid->setTransform(xf);
  const auto d = g.dims();
  auto acc = grid->getAccessor();
  for (int k = 0; k < d[2]; ++k)
    for (int j = 0; j < d[1]; ++j)
      for (int i = 0; i < d[0]; ++i) {
        const std::size_t n = g.linear({i, j, k});
        const float v = g.type() == VoxelType::float32 ? g.floats()[n] : float(g.bytes()[n]);
        if (v != 0.f) acc.setValue(openvdb::Coord(i, j, k), v);
      }
  grid->insertMeta("cgview_dims", openvdb::Vec3IMetadata(openvdb::Vec3i(d[0], d[1], d[2])));
  grid->insertMeta("cgview_type", openvdb::StringMetadata(g.type() == VoxelType::bit     ? "bit"
                                                          : g.type() == VoxelType::uint8 ? "uint8"
                                                                                         : "float32"));
  try {
    openvdb::io::File file(path.string());
    openvdb::GridPtrVec grids{grid};
    file.write(grids);
    file.close();
  } catch (const openvdb::Exception& e) {
    throw IoError("cannot write " + path.string() + ": " + e.what());
  }
}

VoxelGrid read_vdb(const std::filesystem::path& path) {
  init_once();
  openvdb::GridBase::Ptr base;
  try {
    openvdb::io::File file(path.string());
    file.open();
    auto grids = file.getGrids();
    file.close();
    for (auto& g : *grids)
      if (g->isType<openvdb::FloatGrid>() && (!base || g->getName() == "density")) base = g;
    if (!base) throw ParseError(path.string(), "the file holds no float grid", std::nullopt, std::nullopt);
  } catch (const openvdb::Exception& e) {
    throw ParseError(path.string(), std::string("OpenVDB cannot read it: ") + e.what(), std::nullopt, std::nullopt);
  }
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  const auto& xf = grid->transform();
  if (!xf.isLinear()) throw ParseError(path.string(), "the grid's transform is not linear", std::nullopt, std::nullopt);
  const openvdb::Vec3d vs = xf.voxelSize();
  if (std::abs(vs[0] - vs[1]) > 1e-9 * vs[0] || std::abs(vs[0] - vs[2]) > 1e-9 * vs[0])
    throw ParseError(path.string(), "the voxels are not cubes", std::nullopt, std::nullopt);
  openvdb::Coord lo(0, 0, 0);
  std::array<int, 3> d{};
  if (auto meta = grid->getMetadata<openvdb::Vec3IMetadata>("cgview_dims")) {
    d = {meta->value()[0], meta->value()[1], meta->value()[2]};
  } else {
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) throw ParseError(path.string(), "the grid has no active voxels", std::nullopt, std::nullopt);
    lo = box.min();
    d = {box.dim().x(), box.dim().y(), box.dim().z()};
  }
  VoxelType type = VoxelType::float32;
  if (auto meta = grid->getMetadata<openvdb::StringMetadata>("cgview_type")) {
    if (meta->value() == "bit") type = VoxelType::bit;
    else if (meta->value() == "uint8") type = VoxelType::uint8;
  }
  const openvdb::Vec3d c = xf.indexToWorld(lo.asVec3d());
  const double s = vs[0];
  VoxelGrid out(d, Vec3{c[0], c[1], c[2]} - Vec3{0.5, 0.5, 0.5} * s, s, type, std::uint64_t(1) << 34);
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (auto ci = box.begin(); ci; ++ci) {
      const openvdb::Coord q = *ci - lo;
      const VoxelIndex v{q.x(), q.y(), q.z()};
      if (out.contains(v)) out.set(v, *it);
    }
  }
  return out;
}

}  // namespace cgview
