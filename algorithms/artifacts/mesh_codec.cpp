// A mesh artifact: stored as binary PLY, exported in every writable mesh format.
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "io/mesh_formats.h"
#include "io/mesh_io.h"

namespace cgview {

namespace {

class MeshCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::mesh; }
  const std::vector<ArtifactFormat>& formats() const override {
    // The stored form first, then every other writable format.
    static const std::vector<ArtifactFormat> f = [] {
      std::vector<ArtifactFormat> out;
      const MeshFormatInfo& stored = mesh_format_info(MeshFormat::ply);
      out.push_back({stored.name, stored.extensions.front(), stored.mime});
      for (const MeshFormatInfo& i : mesh_formats())
        if (i.write && !i.points_only && &i != &stored) out.push_back({i.name, i.extensions.front(), i.mime});
      return out;
    }();
    return f;
  }
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat& format) const override {
    return write_mesh_bytes(std::get<Mesh>(value), format_from_name(format.name));
  }
  ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json& entry) const override {
    const std::string file = entry.value("file", name + ".ply");
    return read_mesh_bytes(stored, format_from_name(file), file).mesh;
  }
};

}  // namespace

const ArtifactCodec& mesh_codec() {
  static const MeshCodec codec;
  return codec;
}

}  // namespace cgview
