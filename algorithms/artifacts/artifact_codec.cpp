#include "artifacts/artifact_codec.h"

#include <charconv>
#include <nlohmann/json.hpp>

#include "core/ascii.h"
#include "core/errors.h"
#include "io/mesh_io.h"

namespace cgview {

namespace fs = std::filesystem;
using nlohmann::json;

// Each kind's codec, defined in its own file.
const ArtifactCodec& mesh_codec();
const ArtifactCodec& scalar_field_codec();
const ArtifactCodec& voxel_grid_codec();
const ArtifactCodec& skeleton_codec();
const ArtifactCodec& metrics_codec();
const ArtifactCodec& text_codec();
const ArtifactCodec& animation_codec();
const ArtifactCodec& vector_field_codec();
const ArtifactCodec& points_codec();

namespace {

// Stored artifacts are the server's own files, checked when their job ended.
constexpr std::uint64_t kAnySize = ~std::uint64_t(0);

}  // namespace

const ArtifactCodec& artifact_codec(OutputKind kind) {
  switch (kind) {
    case OutputKind::mesh:
      return mesh_codec();
    case OutputKind::scalar_field:
      return scalar_field_codec();
    case OutputKind::voxel_grid:
      return voxel_grid_codec();
    case OutputKind::skeleton:
      return skeleton_codec();
    case OutputKind::metrics:
      return metrics_codec();
    case OutputKind::text:
      return text_codec();
    case OutputKind::animation:
      return animation_codec();
    case OutputKind::vector_field:
      return vector_field_codec();
    case OutputKind::points:
      return points_codec();
  }
  throw InvalidInput("no codec for this artifact kind");
}

const ArtifactCodec* artifact_codec(std::string_view kind_name) {
  for (OutputKind k : kOutputKinds)
    if (kind_name == to_string(k)) return &artifact_codec(k);
  return nullptr;
}

OutputKind kind_of(const ArtifactValue& value) {
  return std::visit([](const auto& v) { return detail::ArtifactKind<std::decay_t<decltype(v)>>::value; }, value);
}

void append_shortest(std::string& s, double v) {
  char buf[32];
  const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, std::size_t(p - buf));
}

std::string ArtifactCodec::noun() const {
  std::string k = to_string(kind());
  for (char& c : k)
    if (c == '_') c = ' ';
  if (kind() == OutputKind::metrics) return "a metrics table";
  if (kind() == OutputKind::points) return "a point cloud";
  if (kind() == OutputKind::text || kind() == OutputKind::animation) return "an " + k;
  return "a " + k;
}

std::string ArtifactCodec::format_list(bool served_only) const {
  std::vector<std::string> names;
  for (const ArtifactFormat& f : formats())
    if (served_only ? f.served : f.written) names.push_back(served_only ? f.name : f.extension);
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return s;
}

const ArtifactFormat& ArtifactCodec::format_of_path(const fs::path& path) const {
  const std::string name = ascii_lower(path.filename().string());
  const ArtifactFormat* best = nullptr;
  for (const ArtifactFormat& f : formats())
    if (f.written && name.size() > f.extension.size() && name.ends_with(f.extension) &&
        (!best || f.extension.size() > best->extension.size()))
      best = &f;
  if (!best)
    throw UnsupportedFormat(noun() + " cannot be saved as '" + ascii_lower(path.extension().string()) + "' (use " +
                            format_list(false) + ")");
  return *best;
}

const ArtifactFormat& ArtifactCodec::format_named(std::string name) const {
  name = ascii_lower(name);
  if (name.empty()) name = served_default();
  for (const ArtifactFormat& f : formats())
    if (f.served && f.name == name) return f;
  throw UnsupportedFormat(noun() + " is served as " + format_list(true) + ", not '" + name + "'");
}

json ArtifactCodec::store(const Artifact& a, const Mesh& input, const fs::path& dir) const {
  const ArtifactFormat& stored = formats().front();
  const std::string file = a.name + stored.extension;
  write_file_bytes(dir / file, encode(a.value, a.name, input, stored));
  return {{"name", a.name}, {"kind", to_string(kind())}, {"file", file}, {"bytes", fs::file_size(dir / file)}};
}

ArtifactValue ArtifactCodec::load(const fs::path& dir, const json& entry) const {
  const std::string file = entry.value("file", "");
  return decode(read_file_bytes(dir / file, kAnySize), entry.value("name", file), entry);
}

void ArtifactCodec::write(const Artifact& a, const Mesh& input, const fs::path& path) const {
  write_file_bytes(path, encode(a.value, a.name, input, format_of_path(path)));
}

ExportedArtifact ArtifactCodec::exported(const fs::path& dir, const json& entry, const std::string& format,
                                         const std::function<Mesh()>& input_mesh) const {
  const ArtifactFormat& f = format_named(format);
  const std::string name = entry.value("name", "");
  const std::string file = entry.value("file", "");
  ExportedArtifact out{"", f.content_type, name + f.extension};
  // The stored file is sent as it is (an older job's may be in another of the kind's formats).
  if (ascii_lower(fs::path(file).extension().string()) == f.extension) {
    out.bytes = read_file_bytes(dir / file, kAnySize);
    return out;
  }
  out.bytes = encode(load(dir, entry), name, needs_mesh(f) ? input_mesh() : Mesh{}, f);
  return out;
}

}  // namespace cgview
