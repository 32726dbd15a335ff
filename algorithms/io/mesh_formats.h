// The mesh file formats, one row each: name, extensions, content type,
// reader, writer and a line of help.  Everything that lists mesh formats is
// made from this table: read_mesh_bytes' and write_mesh_bytes' dispatch,
// format_from_name, the mesh artifact's export formats, the server's content
// types and GET /api/v1/formats (whence the viewer's upload control and
// download links), the routes' and the CLI's help, and the tests' variants.
//
// A new format: its value in MeshFormat (mesh_io.h), its row in
// mesh_formats.cpp, its reader (and writer) in a file of its own under io/,
// that file in algorithms/CMakeLists.txt, and its tests.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.h"

namespace cgview {

// How a format stores numbers, for WriteOptions::binary and the tests'
// variants: text, binary, or either (PLY, STL: binary unless asked).
enum class MeshEncoding { text, binary, either };

struct MeshFormatInfo {
  MeshFormat format;
  const char* name;                     // "glb": the API's ?format= and the CLI's
  std::vector<std::string> extensions;  // ".glb": lowercase, with the dot; the first is the one written
  const char* mime;                     // the content type of a download
  MeshEncoding encoding;
  // Fills result.mesh (validated by read_mesh_bytes) and its warnings.
  void (*read)(std::string_view bytes, const std::string& name, const ReadOptions& options, ReadResult& result);
  // Null: the format is read only (a text glTF needs side files).
  std::string (*write)(const Mesh& mesh, const WriteOptions& options);
  const char* help;  // one line for a user: what the format is and what of it is read
  // The format holds points only, no faces (XYZ, PTS): not a mesh's export
  // format, but a point cloud's (artifacts/points_codec.cpp).
  bool points_only = false;
};

// Every format, in the order they are listed to users.
const std::vector<MeshFormatInfo>& mesh_formats();
const MeshFormatInfo& mesh_format_info(MeshFormat f);
// The format a file extension (".PLY", with the dot; any case) names, or null.
const MeshFormatInfo* mesh_format_of_extension(std::string_view extension);

}  // namespace cgview
