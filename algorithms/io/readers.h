// Internal: one reader and writer per format, used by the table of formats
// (mesh_formats.cpp).
#pragma once

#include <string>
#include <string_view>

#include "core/scalar_field.h"
#include "io/mesh_io.h"

namespace draco {
class PointAttribute;
}

namespace cgview::detail {

// Each reader fills result.mesh (validated by the caller) and its warnings.
void read_off(std::string_view bytes, const std::string& name, ReadResult& result);
void read_obj(std::string_view bytes, const std::string& name, ReadResult& result);
void read_ply(std::string_view bytes, const std::string& name, ReadResult& result);
void read_stl(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result);
void read_draco(std::string_view bytes, const std::string& name, ReadResult& result);
// Point clouds (read_xyz.cpp): XYZ rows, and PTS's count lines and rows.
void read_xyz(std::string_view bytes, const std::string& name, ReadResult& result);
void read_pts(std::string_view bytes, const std::string& name, ReadResult& result);
// Throws ParseError when a Draco stream's header claims more faces than its
// bytes can hold, or more vertices than three a face (Draco's edgebreaker
// decoder allocates for the claim before it reads the stream).
void check_draco_counts(std::string_view bytes, const std::string& name);
// glTF (gltf_io.cpp): binary (.glb) or text (.gltf).
void read_gltf(std::string_view bytes, const std::string& name, bool binary, const ReadOptions& options,
               ReadResult& result);
// `a`, when it holds numbers (or null); throws ParseError naming `what`
// ("positions") when it holds another type (Draco's bool).
const draco::PointAttribute* numeric_draco_attribute(const draco::PointAttribute* a, const std::string& name,
                                                     const char* what);

std::string write_off(const Mesh& mesh);
std::string write_obj(const Mesh& mesh);
std::string write_ply(const Mesh& mesh, bool binary, const ScalarField* field = nullptr);
std::string write_stl(const Mesh& mesh, bool binary);
std::string write_draco(const Mesh& mesh, const WriteOptions& options);
std::string write_glb(const Mesh& mesh);
// The vertices, one a line, with their normals when they are one per vertex.
std::string write_xyz(const Mesh& mesh);

}  // namespace cgview::detail
