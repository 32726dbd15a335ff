// OpenVDB .vdb files: the module libcgview_vdb.so, loaded on first use
// (vdb_module.h says why and what crosses its boundary).
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

#include "voxel/vdb_module.h"

namespace cgview {

namespace {
// Why a read failed, as the program's ParseError will say it.
struct Failed {
  std::string why;
};

void init_once() {
  static const bool done = [] {
    openvdb::initialize();
    return true;
  }();
  (void)done;
}

std::string write_file(const VoxelGrid& g, const std::string& path) {
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
    openvdb::io::File file(path);
    openvdb::GridPtrVec grids{grid};
    file.write(grids);
    file.close();
  } catch (const openvdb::Exception& e) {
    return e.what();
  }
  return "";
}

void read_file(const std::string& path, const vdb_module::Sink& sink) {
  init_once();
  openvdb::GridBase::Ptr base;
  try {
    openvdb::io::File file(path);
    file.open();
    auto grids = file.getGrids();
    file.close();
    for (auto& g : *grids)
      if (g->isType<openvdb::FloatGrid>() && (!base || g->getName() == "density")) base = g;
  } catch (const openvdb::Exception& e) {
    throw Failed{std::string("OpenVDB cannot read it: ") + e.what()};
  }
  if (!base) throw Failed{"the file holds no float grid"};
  auto grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
  const auto& xf = grid->transform();
  if (!xf.isLinear()) throw Failed{"the grid's transform is not linear"};
  const openvdb::Vec3d vs = xf.voxelSize();
  if (std::abs(vs[0] - vs[1]) > 1e-9 * vs[0] || std::abs(vs[0] - vs[2]) > 1e-9 * vs[0])
    throw Failed{"the voxels are not cubes"};
  openvdb::Coord lo(0, 0, 0);
  std::array<int, 3> d{};
  if (auto meta = grid->getMetadata<openvdb::Vec3IMetadata>("cgview_dims")) {
    d = {meta->value()[0], meta->value()[1], meta->value()[2]};
  } else {
    const openvdb::CoordBBox box = grid->evalActiveVoxelBoundingBox();
    if (box.empty()) throw Failed{"the grid has no active voxels"};
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
  sink.start(sink.self, {d, Vec3{c[0], c[1], c[2]} - Vec3{0.5, 0.5, 0.5} * s, s, type});
  for (auto it = grid->cbeginValueOn(); it; ++it) {
    openvdb::CoordBBox box;
    it.getBoundingBox(box);
    for (auto ci = box.begin(); ci; ++ci) {
      const openvdb::Coord q = *ci - lo;
      sink.set(sink.self, {q.x(), q.y(), q.z()}, *it);
    }
  }
}

}  // namespace

}  // namespace cgview

// The module's entry points (vdb_module.h's WriteFn and ReadFn), which
// cgview_voxel looks up.
extern "C" void cgview_vdb_write(const cgview::VoxelGrid& grid, const std::string& path, std::string& why) {
  why = cgview::write_file(grid, path);
}

extern "C" void cgview_vdb_read(const std::string& path, const cgview::vdb_module::Sink& sink, std::string& why) {
  try {
    cgview::read_file(path, sink);
    why.clear();
  } catch (const cgview::Failed& f) {
    why = f.why;
  }
}
