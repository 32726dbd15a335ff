#include "voxel/voxel_io.h"

// The voxel file formats by extension: one file each (binvox.cpp, nrrd.cpp,
// vti.cpp, vox.cpp, raw_voxels.cpp, voxel_vdb.cpp).
#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "voxel/voxel_file_parts.h"

namespace cgview {

namespace {
std::string ext_of(const std::filesystem::path& p) { return ascii_lower(p.extension().string()); }
}  // namespace

const char* voxel_formats() { return ".binvox, .raw, .nrrd, .vti, .vox, .vdb"; }

bool is_voxel_format(const std::filesystem::path& path) {
  const std::string e = ext_of(path);
  return e == ".binvox" || e == ".raw" || e == ".nrrd" || e == ".vti" || e == ".vox" || e == ".vdb";
}

void write_voxel_grid(const VoxelGrid& g, const std::filesystem::path& path) {
  const std::string e = ext_of(path);
  if (e == ".binvox") write_file_bytes(path, encode_binvox(g));
  else if (e == ".nrrd") write_file_bytes(path, encode_nrrd(g));
  else if (e == ".vti") write_file_bytes(path, encode_vti(g));
  else if (e == ".vox") write_file_bytes(path, encode_vox(g));
  else if (e == ".vdb") write_vdb(g, path);
  else if (e == ".raw") voxel_file::write_raw_voxels(g, path);
  else throw UnsupportedFormat("a voxel grid cannot be saved as '" + e + "' (use " + voxel_formats() + " or .vtk)");
}

VoxelGrid read_voxel_grid(const std::filesystem::path& path) {
  const std::string e = ext_of(path), name = path.string();
  if (!is_voxel_format(path))
    throw UnsupportedFormat("'" + e + "' is not a voxel format CGView reads (use " + voxel_formats() + ")");
  if (e == ".vdb") return read_vdb(path);
  if (e == ".raw") return voxel_file::read_raw_voxels(path);
  const std::string bytes = read_file_bytes(path, voxel_file::kMaxRead);
  if (e == ".binvox") return decode_binvox(bytes, name);
  if (e == ".nrrd") return decode_nrrd(bytes, name);
  if (e == ".vti") return decode_vti(bytes, name);
  if (e == ".vox") return decode_vox(bytes, name);
  throw UnsupportedFormat("'" + e + "' is not a voxel format CGView reads (use " + voxel_formats() + ")");
}

}  // namespace cgview
