#include "io/samples.h"

#include <algorithm>
#include <cstdlib>
#include <unistd.h>

#include "io/mesh_io.h"

namespace cgview {

namespace fs = std::filesystem;

std::optional<fs::path> samples_dir() {
  std::vector<fs::path> candidates;
  if (const char* env = std::getenv("CGVIEW_SAMPLES"); env && *env) candidates.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(exe.parent_path().parent_path() / "samples");
#ifdef CGVIEW_BUILD_SAMPLES_DIR
  candidates.emplace_back(CGVIEW_BUILD_SAMPLES_DIR);
#endif
  candidates.emplace_back("/usr/share/cgview/samples");
  for (const fs::path& p : candidates)
    if (fs::is_directory(p, ec)) return p;
  return std::nullopt;
}

std::vector<fs::path> list_samples() {
  std::vector<fs::path> out;
  const auto dir = samples_dir();
  if (!dir) return out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(*dir, ec)) {
    if (!e.is_regular_file()) continue;
    try {
      format_from_name(e.path().string());
      out.push_back(e.path());
    } catch (const std::exception&) {
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::optional<fs::path> resolve_mesh_path(const std::string& name) {
  std::error_code ec;
  if (fs::exists(name, ec)) return fs::path(name);
  if (name.find('/') != std::string::npos) return std::nullopt;
  const auto dir = samples_dir();
  if (!dir) return std::nullopt;
  if (fs::is_regular_file(*dir / name, ec)) return *dir / name;
  for (const fs::path& p : list_samples())
    if (p.stem() == name) return p;
  return std::nullopt;
}

}  // namespace cgview
