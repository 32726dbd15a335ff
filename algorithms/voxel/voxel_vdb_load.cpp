// write_vdb and read_vdb (voxel_io.h): they load the OpenVDB module on
// their first call (vdb_module.h says why it is a module).
#include <vector>

#include "core/errors.h"
#include "core/shared_library.h"
#include "voxel/vdb_module.h"
#include "voxel/voxel_io.h"

#ifdef CGVIEW_VDB_LINKED
// Built into the program instead (the fuzz targets, which have no module beside them).
extern "C" void cgview_vdb_write(const cgview::VoxelGrid& grid, const std::string& path, std::string& why);
extern "C" void cgview_vdb_read(const std::string& path, const cgview::vdb_module::Sink& sink, std::string& why);
#endif

namespace cgview {

namespace {

namespace fs = std::filesystem;

struct Module {
  vdb_module::WriteFn write = nullptr;
  vdb_module::ReadFn read = nullptr;
  std::string why_not;
};

// Beside the running program (build/bin, an installed bin/: a sandboxed
// worker sees its own directory), else where this build put it.
Module load() {
  Module m;
#ifdef CGVIEW_VDB_LINKED
  m.write = &cgview_vdb_write;
  m.read = &cgview_vdb_read;
#else
  std::vector<fs::path> places;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) places.push_back(self.parent_path() / vdb_module::kFile);
  places.push_back(fs::path(CGVIEW_VDB_MODULE_DIR) / vdb_module::kFile);
  for (const fs::path& p : places) {
    if (!fs::exists(p, ec)) continue;
    SharedLibrary lib(p.c_str());
    if (!lib.opened()) {
      m.why_not = lib.why();
      return m;
    }
    m.write = lib.function<vdb_module::WriteFn>(vdb_module::kWrite);
    m.read = lib.function<vdb_module::ReadFn>(vdb_module::kRead);
    if (!m.write || !m.read) m.why_not = p.string() + " is not CGView's OpenVDB module";
    return m;
  }
  m.why_not = std::string("OpenVDB's module ") + vdb_module::kFile + " is neither beside the program (" +
              (places.size() > 1 ? places.front().parent_path().string() : "unknown") + ") nor in " +
              CGVIEW_VDB_MODULE_DIR;
#endif
  return m;
}

const Module& module() {
  static const Module m = load();
  if (!m.write || !m.read) throw IoError(".vdb files are unavailable: " + m.why_not);
  return m;
}

}  // namespace

void write_vdb(const VoxelGrid& grid, const std::filesystem::path& path) {
  std::string why;
  module().write(grid, path.string(), why);
  if (!why.empty()) throw IoError("cannot write " + path.string() + ": " + why);
}

VoxelGrid read_vdb(const std::filesystem::path& path) {
  VoxelGrid out;
  vdb_module::Sink sink;
  sink.self = &out;
  sink.start = [](void* self, const vdb_module::Frame& f) {
    *static_cast<VoxelGrid*>(self) = VoxelGrid(f.dims, f.origin, f.voxel_size, f.type, std::uint64_t(1) << 34);
  };
  sink.set = [](void* self, VoxelIndex v, float value) {
    auto& g = *static_cast<VoxelGrid*>(self);
    if (g.contains(v)) g.set(v, value);
  };
  std::string why;
  module().read(path.string(), sink, why);
  if (!why.empty()) throw ParseError(path.string(), why, std::nullopt, std::nullopt);
  return out;
}

}  // namespace cgview
