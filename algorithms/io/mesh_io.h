// Reading and writing triangle meshes.
//
// Reads OFF, OBJ, PLY (ascii and binary), STL (ascii and binary), Draco
// (.drc), glTF (.glb, .gltf) and the point clouds of XYZ and PTS; writes OFF,
// OBJ, PLY, STL, glTF binary (.glb), Draco (.drc) and XYZ: the table of
// mesh_formats.h says which.  A point cloud is a mesh with no faces
// (core/point_cloud.h): PLY, OBJ and Draco hold one too.  Polygons are fan-triangulated; STL's repeated corners
// are welded into shared vertices; OBJ's vt/vn keep their own indices.
//
// Every reader works on bytes in memory, so a server can parse an upload
// without a file; the path-taking overloads read the file first.  A malformed
// input throws ParseError naming the file and the line (text) or byte offset
// (binary); counts claimed by a header are checked against the bytes present
// before anything is allocated, so a lying header costs nothing.  No reader
// opens a file that the input names: a .gltf's external buffers and images
// (relative URIs) come from ReadOptions::companion, which the caller fills
// with the files uploaded or zipped with it.
#pragma once

#include <cstdint>
#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"

namespace cgview {

// One value a row of mesh_formats() (io/mesh_formats.h).
enum class MeshFormat { off, obj, ply, stl, drc, glb, gltf, xyz, pts };

// "off", "obj", ... as in file extensions.
const char* to_string(MeshFormat f);
// The format named by a path's extension (case-insensitive) or by a bare
// name ("ply").  Throws UnsupportedFormat listing the known ones.
MeshFormat format_from_name(const std::string& path_or_name);
bool can_read(MeshFormat f);
bool can_write(MeshFormat f);  // all but gltf (text glTF needs side files)
// Formats as a user reads them: "off, obj, ply, stl, drc, glb".
std::string writable_formats();
std::string readable_formats();

struct ReadOptions {
  // Files larger than this are refused before being read (InvalidInput).
  std::uint64_t max_bytes = std::uint64_t(4) << 30;
  // Merge STL corners with identical coordinates into shared vertices.
  bool weld_stl = true;
  // glTF: the bytes of a file that a buffer's or an image's "uri" names,
  // given its path relative to the .gltf ('/'-separated, percent-decoded,
  // never absolute, never with a ".." or "." component, never a scheme: the
  // reader refuses those URIs before asking), or nullopt when the caller
  // has no such file.  The bytes must outlive the read.  Unset: only
  // embedded buffers (a .glb's BIN chunk, data: URIs) are read.
  std::function<std::optional<std::string_view>(const std::string& path)> companion;
};

// A material of a glTF: its name, base colour (baseColorFactor's red, green
// and blue, 0..1) and base-colour texture (an index into ReadResult::textures).
struct MeshMaterial {
  std::string name;
  std::optional<std::array<float, 3>> kd;
  std::optional<std::size_t> texture;
};

// An image a material uses: a name for it ("file.png", or "image3.png" for
// an embedded one) and its bytes, PNG or JPEG.
struct MeshTexture {
  std::string name;
  std::string bytes;
};

struct ReadResult {
  Mesh mesh;
  MeshFormat format = MeshFormat::off;
  std::vector<std::string> warnings;  // what was repaired or dropped, for the user
  // A PLY's scalar properties beyond positions, normals, colours and texture
  // coordinates (a "quality", an "sdf" written by another tool): one field
  // each, per vertex, or per face (one value per triangle of mesh.faces).
  std::vector<ScalarField> properties;
  // glTF: the materials the faces use, in order of first use, and each
  // face's index into them (one per face, or empty when the file has no
  // triangles); the images they use.
  std::vector<MeshMaterial> materials;
  std::vector<std::uint32_t> face_material;
  std::vector<MeshTexture> textures;
  // glTF that took bytes from companion files: the same glTF with those as
  // data: URIs, which reads alone (what a server stores); empty otherwise.
  std::string self_contained;
};

// Reads a file; the format comes from its extension.
ReadResult read_mesh_file(const std::filesystem::path& path, const ReadOptions& options = {});
// Reads bytes in a known format; `name` appears in error messages.
ReadResult read_mesh_bytes(std::string_view bytes, MeshFormat format, const std::string& name,
                           const ReadOptions& options = {});
// Shorthand for read_mesh_file(path).mesh.
Mesh read_mesh(const std::filesystem::path& path);

struct WriteOptions {
  bool binary = true;      // PLY and STL: binary (default) or ascii
  int position_bits = 14;  // Draco: position quantization
  int normal_bits = 10;    // Draco
  int uv_bits = 12;        // Draco
  int draco_speed = 5;     // Draco: 0 (best compression) .. 10 (fastest)
};

// Writes a mesh in the format named by the path's extension.
void write_mesh(const Mesh& mesh, const std::filesystem::path& path, const WriteOptions& options = {});
// The bytes of a mesh in a format.
std::string write_mesh_bytes(const Mesh& mesh, MeshFormat format, const WriteOptions& options = {});

// A PLY of the mesh with a scalar field as a float property of its vertices
// or faces, named after the field (MeshLab and ParaView read it).
std::string write_ply_with_field(const Mesh& mesh, const struct ScalarField& field, bool binary = true);

// Writes bytes to a file through a temporary name, so that a failure leaves
// no half-written file; throws IoError, DiskFull when there is no room.
void write_file_bytes(const std::filesystem::path& path, std::string_view bytes);

// Reads a whole file into memory; throws IoError (cannot open) or
// InvalidInput (over max_bytes).
std::string read_file_bytes(const std::filesystem::path& path, std::uint64_t max_bytes);

}  // namespace cgview
