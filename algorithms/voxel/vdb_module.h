#pragma once
// The boundary between the programs and libcgview_vdb.so (voxel_vdb.cpp),
// the OpenVDB module that write_vdb and read_vdb (voxel_io.h) load the
// first time a .vdb file is written or read.  OpenVDB and what it brings
// (log4cplus, Blosc, Boost.IOStreams, TBB) are bound eagerly: linked into a
// program, they cost every start of it ~40 ms, a job's worker and the
// server included, for a format few jobs use.
//
// Plain functions, found with dlsym: the module uses VoxelGrid's inline
// accessors only and calls back into the program for the rest, so that it
// needs none of the program's symbols.  Each sets `why` to "" or to why
// it failed; an exception thrown by a callback passes through.
#include <array>
#include <string>

#include "core/voxel_grid.h"

namespace cgview::vdb_module {

// The grid a file holds, before its voxels.
struct Frame {
  std::array<int, 3> dims{};
  Vec3 origin{};
  double voxel_size = 0;
  VoxelType type = VoxelType::float32;
};

// What read() fills: start() makes the grid (and may throw), then set()
// once a voxel, which ignores voxels outside the grid.
struct Sink {
  void* self = nullptr;
  void (*start)(void* self, const Frame& frame) = nullptr;
  void (*set)(void* self, VoxelIndex v, float value) = nullptr;
};

using WriteFn = void (*)(const VoxelGrid& grid, const std::string& path, std::string& why);
using ReadFn = void (*)(const std::string& path, const Sink& sink, std::string& why);

inline constexpr const char* kFile = "libcgview_vdb.so";
inline constexpr const char* kWrite = "cgview_vdb_write";
inline constexpr const char* kRead = "cgview_vdb_read";

}  // namespace cgview::vdb_module
