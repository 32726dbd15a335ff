// A point cloud artifact (core/point_cloud.h): stored as binary PLY of
// vertices only (exact, and what Open3D, MeshLab and CloudCompare open);
// served by default as a Draco point cloud (what the viewer fetches), and
// exported as ply, drc and every points-only mesh format (xyz).  The files
// are the faceless meshes the mesh writers and readers take.
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "core/point_cloud.h"
#include "io/mesh_formats.h"
#include "io/mesh_io.h"

namespace cgview {

namespace {

class PointsCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::points; }
  const std::vector<ArtifactFormat>& formats() const override {
    // The stored form first.
    static const std::vector<ArtifactFormat> f = [] {
      std::vector<ArtifactFormat> out;
      for (MeshFormat m : {MeshFormat::ply, MeshFormat::drc}) {
        const MeshFormatInfo& i = mesh_format_info(m);
        out.push_back({i.name, i.extensions.front(), i.mime});
      }
      for (const MeshFormatInfo& i : mesh_formats())
        if (i.write && i.points_only) out.push_back({i.name, i.extensions.front(), i.mime});
      return out;
    }();
    return f;
  }
  std::string served_default() const override { return "drc"; }
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat& format) const override {
    const PointCloud& cloud = std::get<PointCloud>(value);
    cloud.validate();
    return write_mesh_bytes(as_mesh(cloud), format_from_name(format.name));
  }
  ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json& entry) const override {
    const std::string file = entry.value("file", name + ".ply");
    return points_of(read_mesh_bytes(stored, format_from_name(file), file).mesh);
  }
};

}  // namespace

const ArtifactCodec& points_codec() {
  static const PointsCodec codec;
  return codec;
}

}  // namespace cgview
