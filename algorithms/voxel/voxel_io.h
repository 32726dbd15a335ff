// Voxel grids in the formats other tools read, written and read back; each
// format is a file of its own (binvox.cpp, raw_voxels.cpp, nrrd.cpp, vti.cpp,
// vox.cpp, voxel_vdb.cpp), voxel_io.cpp picks one by the extension.
//
//   .binvox  binvox 1 (Patrick Min): run-length bytes, y fastest, then z,
//            then x; cubic: the grid is padded with empty voxels to its
//            largest side.  `translate` is the origin, `scale` the cube's side.
//            Occupancy only (any non-zero value is 1).
//   .raw     the values, x fastest (uint8 for bit and uint8 grids, little-endian
//            float32 for float ones), with a sidecar PATH.json (PATH plus
//            ".json": e.raw -> e.raw.json) giving dims, origin, voxel_size, type.
//   .nrrd    NRRD0004, raw encoding, uint8 or float, node-centred samples at the
//            voxel centres (`space origin` = the centre of voxel 0).
//   .vti     VTK XML ImageData, one cell per voxel (CellData "value",
//            Origin = the grid's corner), appended raw binary, UInt64 headers.
//   .vox     MagicaVoxel 150: SIZE and XYZI chunks and a palette; at most 256
//            voxels per side; colour index 1 for occupied bit voxels, the
//            value (1..255) for uint8, the value scaled over 1..255 for float.
//            The format has no origin or voxel size: read back as 0 and 1.
//   .vdb     OpenVDB (voxel_vdb.cpp): a FloatGrid "density" whose index
//            (i, j, k) is voxel (i, j, k); its transform maps index to the
//            voxel's centre; dims in the metadata.
//   .vtk     legacy STRUCTURED_POINTS, ASCII (written by registry/artifact_io).
//
// Throws UnsupportedFormat for another extension, IoError when a file cannot
// be read or written, ParseError for a malformed file, InvalidInput for a
// grid the format cannot hold (.vox over 256 per side).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/voxel_grid.h"

namespace cgview {

// ".binvox .raw .nrrd .vti .vox .vdb" (the formats write_voxel_grid knows).
const char* voxel_formats();
bool is_voxel_format(const std::filesystem::path& path);

void write_voxel_grid(const VoxelGrid& grid, const std::filesystem::path& path);
VoxelGrid read_voxel_grid(const std::filesystem::path& path);

// The same, in memory (all formats but .raw, which is two files, and .vdb).
std::string encode_binvox(const VoxelGrid& grid);
std::string encode_nrrd(const VoxelGrid& grid);
std::string encode_vti(const VoxelGrid& grid);
std::string encode_vox(const VoxelGrid& grid);
VoxelGrid decode_binvox(const std::string& bytes, const std::string& name = "binvox");
VoxelGrid decode_nrrd(const std::string& bytes, const std::string& name = "nrrd");
VoxelGrid decode_vti(const std::string& bytes, const std::string& name = "vti");
VoxelGrid decode_vox(const std::string& bytes, const std::string& name = "vox");

// OpenVDB (voxel_vdb.cpp).
void write_vdb(const VoxelGrid& grid, const std::filesystem::path& path);
VoxelGrid read_vdb(const std::filesystem::path& path);

}  // namespace cgview
