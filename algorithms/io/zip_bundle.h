// The files of a zip bundle, unpacked with libzip: a mesh with its MTL and
// texture images, as the server takes an upload and the CLI a MESH.zip.
// unzip_bundle keeps the files in memory and uses no name as a path on
// disk; BundleDir writes them, names checked, into a private temporary
// directory, so that the mesh is read as a plain file with its companions
// beside it.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"

namespace cgview {

// An upload or a zip (or what it unpacks to) over a limit: a server's 413.
class TooLarge : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

struct BundleFile {
  std::string name;  // as in the zip ("textures/a.png")
  std::string bytes;
};

// The regular files of a zip, directories and macOS's __MACOSX/ and ._NAME
// entries skipped.  Throws InvalidInput
// when the bytes are not a zip, an entry is encrypted or damaged, or a name
// is unsafe (absolute, "..", a drive letter: a zip-slip attempt is refused,
// not tolerated); TooLarge when the entries unpack to more than max_bytes
// in all or there are more than max_files of them.
std::vector<BundleFile> unzip_bundle(std::string_view zip, std::size_t max_bytes, std::size_t max_files = 1000);

// The one mesh file (a name whose extension is a readable format) among a
// bundle's files.  Throws InvalidInput when there is none or more than one.
const BundleFile& bundle_mesh_file(const std::vector<BundleFile>& files);

// A zip file unpacked (unzip_bundle) into a new temporary directory of its
// own (mode 0700), its entries under their names in the zip; removed with
// its files by the destructor.  Throws what unzip_bundle and
// bundle_mesh_file throw, InvalidInput when the zip is larger than
// max_bytes, IoError when the zip cannot be read or its files written.
class BundleDir {
 public:
  explicit BundleDir(const std::filesystem::path& zip, std::size_t max_bytes = std::size_t(4) << 30);
  ~BundleDir();
  BundleDir(const BundleDir&) = delete;
  BundleDir& operator=(const BundleDir&) = delete;
  const std::filesystem::path& dir() const { return dir_; }
  const std::filesystem::path& mesh_path() const { return mesh_path_; }  // the unpacked mesh file
  const std::string& mesh_entry() const { return mesh_entry_; }          // its name in the zip

 private:
  std::filesystem::path dir_, mesh_path_;
  std::string mesh_entry_;
};

}  // namespace cgview
