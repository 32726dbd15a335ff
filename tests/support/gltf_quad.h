// A unit square as glTF ships it: a .gltf whose one buffer is an external
// file, and that file's bytes (4 float positions, 6 uint16 indices), for the
// tests of the reader, the CLI and the server (header-only).
#pragma once

#include <cstdint>
#include <cstring>
#include <string>

namespace cgview::test {

// The .gltf, its buffer's uri as given (percent-encoded, relative, or hostile).
inline std::string gltf_quad(const std::string& uri) {
  return R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
         R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],)"
         R"("accessors":[{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3"},)"
         R"({"bufferView":1,"componentType":5123,"count":6,"type":"SCALAR"}],)"
         R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":48},{"buffer":0,"byteOffset":48,"byteLength":12}],)"
         R"("buffers":[{"byteLength":60,"uri":")" +
         uri + R"("}]})";
}

// The .bin's 60 bytes, little-endian.
inline std::string gltf_quad_bin() {
  std::string s;
  for (const float x : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) {
    char b[4];
    std::memcpy(b, &x, 4);
    s.append(b, 4);
  }
  for (const std::uint16_t i : {0, 1, 2, 0, 2, 3}) s += {char(i & 0xff), char(i >> 8)};
  return s;
}

}  // namespace cgview::test
