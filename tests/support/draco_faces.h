// The faces of a Draco stream as Draco's own decoder reads them, each with
// the material that CGView's "material" attribute gives its corners: what
// the tests compare with the mesh the stream was written from.
#pragma once

#include <draco/compression/decode.h>

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

namespace cgview::test {

struct DracoFace {
  std::array<std::array<float, 3>, 3> corners{};
  // The material of its first corner, or kNoMaterial when the stream has none.
  std::uint32_t material = kNoMaterialValue;
  // Whether the three corners have the same material.
  bool one_material = true;
  static constexpr std::uint32_t kNoMaterialValue = 0xFFFFFFFFu;
};
inline constexpr std::uint32_t kNoMaterial = DracoFace::kNoMaterialValue;

// Empty when Draco cannot decode the bytes as a mesh.
inline std::vector<DracoFace> draco_faces(std::string_view bytes) {
  draco::DecoderBuffer buf;
  buf.Init(bytes.data(), bytes.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buf);
  if (!decoded.ok()) return {};
  const draco::Mesh& mesh = *decoded.value();
  const draco::PointAttribute* pos = mesh.GetNamedAttribute(draco::GeometryAttribute::POSITION);
  const int mat_id = mesh.GetAttributeIdByMetadataEntry("name", "material");
  const draco::PointAttribute* mat = mat_id >= 0 ? mesh.attribute(mat_id) : nullptr;
  std::vector<DracoFace> out(mesh.num_faces());
  for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f) {
    DracoFace& face = out[f.value()];
    for (int k = 0; k < 3; ++k) {
      const draco::PointIndex p = mesh.face(f)[k];
      pos->ConvertValue<float>(pos->mapped_index(p), 3, face.corners[k].data());
      if (!mat) continue;
      std::uint32_t m = 0;
      mat->ConvertValue<std::uint32_t>(mat->mapped_index(p), 1, &m);
      if (k == 0) face.material = m;
      else if (m != face.material) face.one_material = false;
    }
  }
  return out;
}

}  // namespace cgview::test
