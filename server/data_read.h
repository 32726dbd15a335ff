// Data of the kinds jobs make, uploaded like meshes: a voxel grid, a curve
// skeleton or a scalar field made by another tool.  Read here (in a child
// process, as mesh uploads are), each becomes the artifact its kind's codec
// stores (artifacts/artifact_codec.h), so that it shows, slices, compares
// and feeds jobs exactly as a job's result does.
//
//   voxel grid    .nrrd .binvox .vti .vox .vdb (voxel/voxel_io.h)
//   skeleton      .polylines.txt .polylines .cg .obj .json (io/skeleton_io.h)
//   scalar field  .ply whose vertices or faces carry a scalar property (the
//                 first one, or the one named), or .txt with one value a
//                 line ("nan": no value), for a stored mesh with as many
//                 vertices (a per-vertex field) or faces (per face)
#pragma once

#include <cstddef>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "upload_read.h"

namespace cgview::server {

struct DataRequest {
  std::string name;      // the file's name: its extension says its format
  std::string kind;      // "voxel_grid", "skeleton", "scalar_field", or "" (from the name)
  std::string property;  // a PLY's property to take as the field ("": the first)
  // The stored mesh a field is for: its counts (a field must match one).
  bool for_mesh = false;
  std::size_t mesh_vertices = 0, mesh_faces = 0;
};

struct DataRead {
  nlohmann::json entry;               // the artifact's entry, as a worker lists it
  std::vector<std::string> warnings;  // what was not used, or has no value
};

// The kind ("voxel_grid", ...) an upload named `name` is, or the one asked
// for if the name allows it.  Throws UnsupportedFormat, InvalidInput.
std::string data_kind(const std::string& name, const std::string& kind);

// Reads the upload and stores its artifact into `out_dir` by its kind's
// codec.  Throws InvalidInput (a bad file, a field that fits no count of
// the mesh), UnsupportedFormat, TooLarge.
DataRead read_data(const DataRequest& request, std::string_view bytes, const std::filesystem::path& out_dir);

// read_data in a child process (`reader.program --read-data DIR`: the
// server runs cgview-read-data, beside cgview-read) under the reader's
// limits; the artifact's files are moved into `out_dir`.  Throws
// what read_data throws, as run_reader_child says.
DataRead read_data_in_child(const UploadReader& reader, const DataRequest& request, std::string_view bytes,
                            const std::filesystem::path& out_dir);

// The child's side: DIR/request.json and DIR/upload in; DIR/out/ (the
// artifact's files) and DIR/result.json ({"entry", "warnings"}) out.
int read_data_main(const std::filesystem::path& dir);

}  // namespace cgview::server
