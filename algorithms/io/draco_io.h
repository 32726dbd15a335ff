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

// The Draco bytes of a mesh whose face f has material face_material[f] (one
// entry per face; empty: as write_mesh_bytes(mesh, drc)).  Vertices on a
// boundary between materials are split, one point per material.
std::string write_draco_with_materials(const Mesh& mesh, std::span<const std::uint32_t> face_material,
                                       const WriteOptions& options = {});

// Draco renumbers vertices and faces (Edgebreaker's traversal).  Where each
// decoded point and face of a stream came from.
struct DracoStoredOrder {
  std::vector<std::uint32_t> points;  // one per decoded point: its vertex in the written mesh
  std::vector<std::uint32_t> faces;   // one per decoded face: its face in the written mesh (corners may be turned)
};

// The stored order of `bytes`, the Draco stream that
// write_draco_with_materials(written, face_material, options) wrote: the mesh
// is written again with each point's vertex index as an attribute, which
// Draco keeps through its renumbering, and that stream is checked to decode
// to exactly the points and faces `bytes` decodes to.  Throws InvalidInput
// when it does not, or when a decoded face is none of `written`'s.
DracoStoredOrder draco_stored_order(std::string_view bytes, const Mesh& written,
                                    std::span<const std::uint32_t> face_material, const WriteOptions& options = {});

}  // namespace cgview
