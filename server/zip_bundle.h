// The files of a zip upload, unpacked in memory (libzip): a mesh with its
// MTL and texture images.  Names inside the zip are only ever compared with
// names that the mesh's files mention; none is used as a path on disk.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/errors.h"

namespace cgview::server {

// An upload (or what it unpacks to) over the server's limit: a 413.
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

}  // namespace cgview::server
