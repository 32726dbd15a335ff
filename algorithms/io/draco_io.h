// Draco with a material per face: what the viewer draws as geometry groups,
// one three.js material each.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "io/mesh_io.h"

namespace cgview {

// The name (metadata entry "name") of the GENERIC attribute that carries
// each point's material index.
inline constexpr const char* kDracoMaterialAttribute = "material";

// The name of the GENERIC attribute that carries each point's vertex index in
// the mesh that was written (WriteOptions::stored_ids).
inline constexpr const char* kDracoVertexIdAttribute = "vertex_id";

// The Draco bytes of a mesh whose face f has material face_material[f] (one
// entry per face; empty: as write_mesh_bytes(mesh, drc)).  Vertices on a
// boundary between materials are split, one point per material.
std::string write_draco_with_materials(const Mesh& mesh, std::span<const std::uint32_t> face_material,
                                       const WriteOptions& options = {});

// Draco renumbers faces (Edgebreaker's traversal): for each face that a
// decoder reads from `draco` (written from `written` with stored_ids), in the
// decoder's order, the index of the face of `written` it is; a face's
// corners may come rotated.  One value per decoded face.  Throws
// InvalidInput when the bytes carry no vertex ids, or a decoded face is none
// of `written`'s.
std::vector<std::uint32_t> draco_face_order(std::string_view draco, const Mesh& written);

}  // namespace cgview
