// The sample meshes (CGAL's data set from Debian's libcgal-demo, unpacked
// into build/samples by CMake), found without the user copying anything.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace cgview {

// The first existing directory of: $CGVIEW_SAMPLES, <this program's
// directory>/../samples, the build tree's samples, /usr/share/cgview/samples.
std::optional<std::filesystem::path> samples_dir();
// Sample mesh files, sorted by name.
std::vector<std::filesystem::path> list_samples();
// A path as given when it exists; else a sample of that name, with or
// without its extension ("elephant", "elephant.off").  Empty if neither.
std::optional<std::filesystem::path> resolve_mesh_path(const std::string& name_or_path);

}  // namespace cgview
