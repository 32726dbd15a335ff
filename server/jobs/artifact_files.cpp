#include "jobs/artifact_files.h"

#include "artifacts/artifact_codec.h"

namespace cgview::server {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// A file name of the directory itself, and none of the server's own
// (result.json and stderr.txt are written beside the artifacts).
bool plain_name(const std::string& file) {
  return !file.empty() && file.size() <= 255 && file.find('/') == std::string::npos && file != "." && file != ".." &&
         file != "result.json" && file != "stderr.txt";
}

}  // namespace

std::string incomplete_artifact(const JobDir& dir, const json& artifacts, std::uint64_t max_bytes) {
  if (!artifacts.is_array()) return "no artifact list";
  if (artifacts.size() > kMaxArtifacts)
    return std::to_string(artifacts.size()) + " artifacts, over the limit of " + std::to_string(kMaxArtifacts);
  std::uint64_t total = 0;
  for (const auto& a : artifacts) {
    const std::string name = a.is_object() ? a.value("name", "") : "";
    const std::string file = a.is_object() ? a.value("file", "") : "";
    if (name.empty() || !plain_name(file)) return "an artifact without a name or a file";
    std::string why;
    const auto size = dir.size_of(file, &why);
    if (!size) return "artifact '" + name + "': " + (why.empty() ? "its file is missing" : why);
    if (a.value("kind", "") == "scalar_field") {
      const json count = a.value("count", json());
      if (!count.is_number_unsigned() || *size != count.get<std::uint64_t>() * sizeof(float))
        return "artifact '" + name + "': " + std::to_string(*size) + " bytes for " + count.dump() + " values";
    } else if (*size == 0 && a.value("kind", "") != "text") {  // an extracted message may be empty
      return "artifact '" + name + "': its file is empty";
    }
    const json bytes = a.value("bytes", json());
    if (!bytes.is_number_unsigned()) return "artifact '" + name + "': its size is not said";
    if (*size != bytes.get<std::uint64_t>())
      return "artifact '" + name + "': " + std::to_string(*size) + " bytes of the " + bytes.dump() + " written";
    total += *size;
    if (total > max_bytes)
      return "its artifacts take more than the " + std::to_string(max_bytes) +
             " bytes its owner has left under their storage quota";
  }
  return "";
}

std::string take_artifacts(const JobDir& work, const json& artifacts, const fs::path& to, bool whole) {
  std::error_code ec;
  fs::remove_all(to, ec);
  fs::create_directories(to, ec);
  if (ec) return "cannot make " + to.string() + ": " + ec.message();
  std::string why;
  for (const auto& a : artifacts) {
    const std::string file = a.value("file", "");
    const std::uint64_t bytes = a.value("bytes", std::uint64_t(0));
    if (!(whole ? work.move(file, to / file, bytes, &why) : work.copy(file, to / file, bytes, &why))) break;
    const ArtifactCodec* codec = artifact_codec(a.value("kind", ""));
    for (const std::string& side : codec ? codec->side_files(a) : std::vector<std::string>{}) {
      if (!plain_name(side) || fs::exists(to / side, ec)) continue;
      const auto taken = whole ? work.move(side, to / side, kMaxSideFileBytes, &why)
                               : work.copy(side, to / side, kMaxSideFileBytes, &why);
      if (!taken && !why.empty()) break;
      why.clear();
    }
    if (!why.empty()) break;
  }
  if (why.empty()) return "";
  fs::remove_all(to, ec);
  return why;
}

}  // namespace cgview::server
