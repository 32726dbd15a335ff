// A curve skeleton artifact: stored as OBJ (v and l records, which MeshLab
// and Blender open); exported in every skeleton file of io/skeleton_io.h.
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "io/skeleton_io.h"

namespace cgview {

namespace {

SkeletonFormat skeleton_format(const ArtifactFormat& f) {
  return f.name == "polylines" ? SkeletonFormat::polylines
         : f.name == "cg"      ? SkeletonFormat::cg
         : f.name == "json"    ? SkeletonFormat::json
                               : SkeletonFormat::obj;
}

class SkeletonCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::skeleton; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {{"obj", ".obj", "text/plain; charset=utf-8"},
                                                  {"cg", ".cg", "text/plain; charset=utf-8"},
                                                  {"json", ".json", "application/json"},
                                                  {"polylines", ".polylines.txt", "text/plain; charset=utf-8"}};
    return f;
  }
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat& format) const override {
    return write_skeleton_bytes(std::get<Skeleton>(value), skeleton_format(format));
  }
  ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json& entry) const override {
    const std::string file = entry.value("file", name + ".obj");
    return read_skeleton_bytes(stored, skeleton_format_from_name(file), file);
  }
  // ".polylines" names CGAL's polylines too, as the skeleton readers take it.
  const ArtifactFormat& format_of_path(const std::filesystem::path& path) const override {
    const SkeletonFormat f = skeleton_format_from_name(path.filename().string());  // throws naming the formats
    for (const ArtifactFormat& a : formats())
      if (skeleton_format(a) == f) return a;
    return formats().front();
  }
};

}  // namespace

const ArtifactCodec& skeleton_codec() {
  static const SkeletonCodec codec;
  return codec;
}

}  // namespace cgview
