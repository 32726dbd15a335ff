// A text artifact (a message extracted by chaos_extract): its bytes as they
// are, which need not be UTF-8, as .txt or .bin.
#include "artifacts/artifact_codec.h"

namespace cgview {

namespace {

class TextCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::text; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {{"txt", ".txt", "application/octet-stream"},
                                                  {"bin", ".bin", "application/octet-stream"}};
    return f;
  }
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat&) const override {
    return std::get<Text>(value).bytes;
  }
  ArtifactValue decode(std::string_view stored, const std::string&, const nlohmann::json&) const override {
    return Text{std::string(stored)};
  }
};

}  // namespace

const ArtifactCodec& text_codec() {
  static const TextCodec codec;
  return codec;
}

}  // namespace cgview
