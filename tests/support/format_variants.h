// Every writable format as the tests write it: PLY and STL in ascii and binary.
#pragma once

#include <string>
#include <vector>

#include "io/mesh_formats.h"
#include "io/mesh_io.h"

namespace cgview::test {

struct Variant {
  std::string label;  // "ply_binary"
  MeshFormat format;
  bool binary;
  std::string ext;  // "ply"
  bool text() const { return !binary; }
};

// Made from the table of formats: one variant a writable format, two (ascii
// and binary) where WriteOptions::binary chooses.
inline const std::vector<Variant>& variants() {
  static const std::vector<Variant> v = [] {
    std::vector<Variant> out;
    for (const MeshFormatInfo& f : mesh_formats()) {
      if (!f.write || f.points_only) continue;  // a cloud's format: no faces to compare
      const std::string ext = f.extensions.front().substr(1);
      if (f.encoding == MeshEncoding::either) {
        out.push_back({std::string(f.name) + "_ascii", f.format, false, ext});
        out.push_back({std::string(f.name) + "_binary", f.format, true, ext});
      } else {
        out.push_back({f.name, f.format, f.encoding == MeshEncoding::binary, ext});
      }
    }
    return out;
  }();
  return v;
}

}  // namespace cgview::test
