// An animation artifact (chaos_animate's frames): stored and exported in
// the .frames format of core/animation.h (the faces once, then each frame's
// positions quantized to uint16).
#include "artifacts/artifact_codec.h"
#include "core/animation.h"

namespace cgview {

namespace {

class AnimationCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::animation; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {{"frames", ".frames", "application/octet-stream"}};
    return f;
  }
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat&) const override {
    return encode_frames(std::get<Animation>(value));
  }
  ArtifactValue decode(std::string_view stored, const std::string&, const nlohmann::json&) const override {
    return decode_frames(stored);
  }
};

}  // namespace

const ArtifactCodec& animation_codec() {
  static const AnimationCodec codec;
  return codec;
}

}  // namespace cgview
