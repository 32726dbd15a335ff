// A scalar field artifact: stored as its raw little-endian float32 values
// (NAME.f32, what the viewer and numpy read directly) with NAME.field.json
// beside it (the field's own name); the list entry carries its location,
// colour hint, range and count.  Exported as f32, json, txt (one value a
// line, in vertex or face order), csv (index,value) or ply (the input mesh
// with the values as a float property, for MeshLab and ParaView).
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"

namespace cgview {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

ColorHint hint_named(const std::string& hint) {
  return hint == "symmetric"     ? ColorHint::symmetric
         : hint == "magnitude"   ? ColorHint::magnitude
         : hint == "categorical" ? ColorHint::categorical
                                 : ColorHint::standard;
}

class ScalarFieldCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::scalar_field; }
  const std::vector<ArtifactFormat>& formats() const override {
    // f32 and json are what the viewer and scripts read over HTTP; a file
    // for people is txt, csv or ply.
    static const std::vector<ArtifactFormat> f = {{"f32", ".f32", "application/octet-stream", true, false},
                                                  {"json", ".json", "application/json", true, false},
                                                  {"txt", ".txt", "text/plain; charset=utf-8"},
                                                  {"csv", ".csv", "text/csv"},
                                                  {"ply", ".ply", "application/octet-stream"}};
    return f;
  }
  // Served with its name, location, hint and range, as the viewer reads it.
  std::string served_default() const override { return "json"; }
  // `cgview run` writes a field for people and spreadsheets.
  std::string default_extension() const override { return ".txt"; }
  bool needs_mesh(const ArtifactFormat& f) const override { return f.name == "ply"; }

  std::string encode(const ArtifactValue& value, const std::string&, const Mesh& input,
                     const ArtifactFormat& format) const override {
    const ScalarField& f = std::get<ScalarField>(value);
    if (format.name == "f32")
      return std::string(reinterpret_cast<const char*>(f.values.data()), f.values.size() * sizeof(float));
    if (format.name == "ply") return write_ply_with_field(input, f);
    if (format.name == "json") {
      const auto [lo, hi] = f.range();
      json values = json::array();
      for (float v : f.values) values.push_back(v);  // NaN (no value) becomes null
      return json{{"name", f.name},
                  {"location", to_string(f.location)},
                  {"hint", to_string(f.hint)},
                  {"range", {lo, hi}},
                  {"values", values}}
          .dump();
    }
    const bool csv = format.name == "csv";
    std::string out;
    if (csv) out = std::string(to_string(f.location)) + "," + f.name + "\n";
    for (std::size_t i = 0; i < f.values.size(); ++i) {
      if (csv) out += std::to_string(i) + ",";
      append_shortest(out, f.values[i]);
      out += '\n';
    }
    return out;
  }

  ArtifactValue decode(std::string_view stored, const std::string& name, const json& entry) const override {
    if (stored.size() % sizeof(float) != 0)
      throw ParseError(name + ".f32", std::to_string(stored.size()) + " bytes are not whole float32 values",
                       std::nullopt, stored.size());
    ScalarField f;
    f.name = name;
    f.location = entry.value("location", "vertex") == "face" ? Location::face : Location::vertex;
    f.hint = hint_named(entry.value("hint", "standard"));
    f.values.resize(stored.size() / sizeof(float));
    std::memcpy(f.values.data(), stored.data(), stored.size());
    return f;
  }

  json store(const Artifact& a, const Mesh& input, const fs::path& dir) const override {
    json entry = ArtifactCodec::store(a, input, dir);
    const ScalarField& f = std::get<ScalarField>(a.value);
    const auto [lo, hi] = f.range();
    entry["location"] = to_string(f.location);
    entry["hint"] = to_string(f.hint);
    entry["range"] = {lo, hi};
    entry["count"] = f.values.size();
    write_file_bytes(dir / (a.name + ".field.json"), json{{"name", f.name},
                                                          {"location", entry["location"]},
                                                          {"hint", entry["hint"]},
                                                          {"range", entry["range"]},
                                                          {"count", entry["count"]}}
                                                         .dump());
    return entry;
  }

  std::vector<std::string> side_files(const json& entry) const override {
    return {entry.value("name", "") + ".field.json"};
  }

  ArtifactValue load(const fs::path& dir, const json& entry) const override {
    ArtifactValue v = ArtifactCodec::load(dir, entry);
    // The field's own name, where it differs from the artifact's.
    std::error_code ec;
    const fs::path side = dir / (entry.value("name", "") + ".field.json");
    if (fs::is_regular_file(side, ec)) {
      const json s = parse_json_or_discarded(read_file_bytes(side, 1 << 20));
      if (s.is_object() && s.contains("name") && s["name"].is_string())
        std::get<ScalarField>(v).name = s["name"].get<std::string>();
    }
    return v;
  }
};

}  // namespace

const ArtifactCodec& scalar_field_codec() {
  static const ScalarFieldCodec codec;
  return codec;
}

}  // namespace cgview
