// chaos_decrypt: inverts chaos_encrypt (chaos/encrypt.h): with the right key
// the float32 positions and the faces come back bit for bit; a wrong key
// gives an unrecognizable mesh, not an error.  Teaching and research code,
// not vetted cryptography: see docs/CHAOS.md.
//
//   Mesh cipher = read_mesh("cipher.ply");
//   ChaosDecryptResult r = chaos_decrypt(cipher, {.key = "my key"});
//   write_mesh(r.mesh, "plain.ply");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ChaosDecryptParams {
  std::string key = "";
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "the key the mesh was encrypted with"});
  }
};

struct ChaosDecryptResult {
  Mesh mesh;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for an empty key or a mesh of fewer than 2 vertices.
ChaosDecryptResult chaos_decrypt(const Mesh& mesh, const ChaosDecryptParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
