// Every writable format as the tests write it: PLY and STL in ascii and binary.
#pragma once

#include <string>
#include <vector>

#include "io/mesh_io.h"

namespace cgview::test {

struct Variant {
  std::string label;  // "ply_binary"
  MeshFormat format;
  bool binary;
  std::string ext;  // "ply"
  bool text() const { return !binary; }
};

inline const std::vector<Variant>& variants() {
  static const std::vector<Variant> v = {
      {"off", MeshFormat::off, false, "off"},       {"obj", MeshFormat::obj, false, "obj"},
      {"ply_ascii", MeshFormat::ply, false, "ply"}, {"ply_binary", MeshFormat::ply, true, "ply"},
      {"stl_ascii", MeshFormat::stl, false, "stl"}, {"stl_binary", MeshFormat::stl, true, "stl"},
      {"drc", MeshFormat::drc, true, "drc"},        {"glb", MeshFormat::glb, true, "glb"}};
  return v;
}

}  // namespace cgview::test
