#include "io/mesh_formats.h"

#include "core/ascii.h"
#include "core/errors.h"
#include "io/readers.h"

namespace cgview {

const std::vector<MeshFormatInfo>& mesh_formats() {
  using E = MeshEncoding;
  using Opts = const ReadOptions&;
  static const std::vector<MeshFormatInfo> table = {
      {MeshFormat::off,
       "off",
       {".off"},
       "application/octet-stream",
       E::text,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_off(b, n, r); },
       [](const Mesh& m, const WriteOptions&) { return detail::write_off(m); },
       "Object File Format (Geomview, CGAL): text; polygons are fan-triangulated"},
      {MeshFormat::obj,
       "obj",
       {".obj"},
       "model/obj",
       E::text,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_obj(b, n, r); },
       [](const Mesh& m, const WriteOptions&) { return detail::write_obj(m); },
       "Wavefront OBJ: text; texture coordinates and normals, and the MTL's materials and textures zipped with it"},
      {MeshFormat::ply,
       "ply",
       {".ply"},
       "application/octet-stream",
       E::either,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_ply(b, n, r); },
       [](const Mesh& m, const WriteOptions& o) { return detail::write_ply(m, o.binary); },
       "Stanford PLY, ascii or binary: normals, colours, texture coordinates; other vertex and face properties as "
       "scalar fields"},
      {MeshFormat::stl,
       "stl",
       {".stl"},
       "model/stl",
       E::either,
       [](std::string_view b, const std::string& n, Opts o, ReadResult& r) { detail::read_stl(b, n, o, r); },
       [](const Mesh& m, const WriteOptions& o) { return detail::write_stl(m, o.binary); },
       "STL, ascii or binary: triangles whose equal corners are welded into shared vertices"},
      {MeshFormat::drc,
       "drc",
       {".drc"},
       "application/octet-stream",
       E::binary,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_draco(b, n, r); },
       [](const Mesh& m, const WriteOptions& o) { return detail::write_draco(m, o); },
       "Google's Draco compressed mesh: positions quantized (14 bits when written)"},
      {MeshFormat::glb,
       "glb",
       {".glb"},
       "model/gltf-binary",
       E::binary,
       [](std::string_view b, const std::string& n, Opts o, ReadResult& r) { detail::read_gltf(b, n, true, o, r); },
       [](const Mesh& m, const WriteOptions&) { return detail::write_glb(m); },
       "glTF 2.0 binary: the default scene's triangles (Draco-compressed too), with materials and textures"},
      {MeshFormat::gltf,
       "gltf",
       {".gltf"},
       "model/gltf+json",
       E::text,
       [](std::string_view b, const std::string& n, Opts o, ReadResult& r) { detail::read_gltf(b, n, false, o, r); },
       nullptr,
       "glTF 2.0 text: its .bin buffers and images as data: URIs or zipped with it"},
      {MeshFormat::xyz,
       "xyz",
       {".xyz"},
       "text/plain; charset=utf-8",
       E::text,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_xyz(b, n, r); },
       [](const Mesh& m, const WriteOptions&) { return detail::write_xyz(m); },
       "XYZ point cloud: text, one point a line, x y z [nx ny nz]; written without colours",
       true},
      {MeshFormat::pts,
       "pts",
       {".pts"},
       "text/plain; charset=utf-8",
       E::text,
       [](std::string_view b, const std::string& n, Opts, ReadResult& r) { detail::read_pts(b, n, r); },
       nullptr,
       "Leica PTS point cloud: text, a count line, then x y z [intensity [r g b]] a point (intensities dropped)",
       true},
  };
  return table;
}

const MeshFormatInfo& mesh_format_info(MeshFormat f) {
  for (const MeshFormatInfo& i : mesh_formats())
    if (i.format == f) return i;
  throw Error("a mesh format without a row in mesh_formats()");
}

const MeshFormatInfo* mesh_format_of_extension(std::string_view extension) {
  const std::string ext = ascii_lower(std::string(extension));
  for (const MeshFormatInfo& i : mesh_formats())
    for (const std::string& e : i.extensions)
      if (e == ext) return &i;
  return nullptr;
}

}  // namespace cgview
