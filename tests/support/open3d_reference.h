// Open3D (Debian's python3-open3d, run by /usr/bin/python3: another
// python3 may come first on PATH) as the reference reader of point cloud
// files: what it reads of a PLY, XYZ or PTS that we wrote, and the files it
// writes for our readers.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "test_support.h"

namespace cgview::test {

inline constexpr const char* kSystemPython = "/usr/bin/python3";

// Whether /usr/bin/python3 imports open3d (setup.sh installs python3-open3d).
inline bool have_open3d() {
  static const bool ok = run(std::string(kSystemPython) + " -c 'import open3d' 2>/dev/null") == 0;
  return ok;
}

// The cloud Open3D reads from `path` (format: Open3D's name, "auto" from
// the extension, "xyzn" for XYZ with normals): {"points": [[x, y, z]...],
// "normals": [...], "colors": [[r, g, b] in 0..1 ...]}, or nullopt with the
// tool's output in `log` when it fails.
inline std::optional<nlohmann::json> open3d_read(const std::filesystem::path& path, const std::string& format,
                                                 std::string* log) {
  const std::string script =
      "import json, sys, open3d as o3d\n"
      "pc = o3d.io.read_point_cloud(sys.argv[1], format=sys.argv[2])\n"
      "print(json.dumps({'points': pc.points, 'normals': pc.normals, 'colors': pc.colors},"
      " default=lambda v: [list(x) for x in v]))\n";
  const std::filesystem::path py = temp_dir("open3d") / "read.py";  // never beside a committed file
  write_text(py, script);
  std::string out;
  if (run(std::string(kSystemPython) + " '" + py.string() + "' '" + path.string() + "' " + format + " 2>&1", &out) !=
      0) {
    if (log) *log = out;
    return std::nullopt;
  }
  // Open3D may print warnings before the line.
  const auto at = out.rfind("{\"points\"");
  if (at == std::string::npos) {
    if (log) *log = out;
    return std::nullopt;
  }
  return nlohmann::json::parse(out.substr(at));
}

}  // namespace cgview::test
