// A metrics table artifact (name -> number): stored and exported as JSON.
#include <cmath>
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "core/errors.h"
#include "io/parse_json.h"

namespace cgview {

namespace {

class MetricsCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::metrics; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {{"json", ".json", "application/json"}};
    return f;
  }
  // Through nlohmann so that names are escaped and a NaN or infinity, which
  // JSON cannot hold, becomes null.
  std::string encode(const ArtifactValue& value, const std::string&, const Mesh&,
                     const ArtifactFormat&) const override {
    return nlohmann::json(std::get<Metrics>(value)).dump() + "\n";
  }
  ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json&) const override {
    const nlohmann::json j = parse_json_or_discarded(stored);
    if (!j.is_object())
      throw ParseError(name + ".json", "metrics are a JSON object of numbers", std::nullopt, std::nullopt);
    Metrics m;
    for (const auto& [key, v] : j.items()) m[key] = v.is_number() ? v.get<double>() : std::nan("");
    return m;
  }
};

}  // namespace

const ArtifactCodec& metrics_codec() {
  static const MetricsCodec codec;
  return codec;
}

}  // namespace cgview
