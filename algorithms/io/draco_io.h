// Draco with a material per face: what the viewer draws as geometry groups,
// one three.js material each.
#pragma once

#include <cstdint>
#include <span>
#include <string>

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

}  // namespace cgview
