// Materials beside a mesh file: an OBJ's MTL libraries and `usemtl`
// groups, and a PLY's `comment TextureFile` (MeshLab's).  These only name
// files; which bytes those names stand for is the caller's business (the
// server looks them up among the files of one upload, by base name), so no
// reader here ever opens a path that a file names.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cgview {

// One `newmtl` of an MTL file.
struct Material {
  std::string name;
  std::optional<std::array<float, 3>> kd;  // diffuse colour, 0..1
  std::string map_kd;                      // the diffuse texture's file name as written, or empty
};

// The materials of an MTL file, in file order (unknown statements are skipped).
std::vector<Material> parse_mtl(std::string_view bytes);

// What an OBJ says about materials: its `mtllib` files, how many triangles
// each `usemtl` name covers (faces before any usemtl count under ""), and
// the material of every triangle.  Polygons count as the triangles
// read_obj fans them into, so face_material follows the read mesh's faces.
struct ObjMaterialUse {
  std::vector<std::string> libraries;
  std::map<std::string, std::size_t> faces;
  std::vector<std::string> names;            // the materials used, in order of first use
  std::vector<std::uint32_t> face_material;  // per triangle: an index into names
};
ObjMaterialUse obj_material_use(std::string_view obj_bytes);

// The file named by a PLY header's `comment TextureFile NAME`, or empty.
std::string ply_texture_file(std::string_view ply_bytes);

// The last part of a path written on Windows or Unix (".\\tex\\a.png" ->
// "a.png"): how a referenced file is matched against uploaded names.
std::string file_base_name(std::string_view path);

// "image/png" or "image/jpeg" from an image's first bytes; empty otherwise.
std::string image_mime_type(std::string_view bytes);

}  // namespace cgview
