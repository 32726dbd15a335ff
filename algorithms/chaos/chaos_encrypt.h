// chaos_encrypt: keyed, reversible scrambling of a mesh's vertex positions,
// vertex order and face order by chaotic sequences (chaos/encrypt.h);
// chaos_decrypt inverts it.  Teaching and research code, not vetted
// cryptography: see docs/CHAOS.md.
//
//   Mesh m = read_mesh("elephant.off");
//   ChaosEncryptResult r = chaos_encrypt(m, {.key = "my key"});
//   std::cout << r.metrics.at("key_sensitivity_changed_coordinates");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ChaosEncryptParams {
  std::string key = "";
  bool measure = true;
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "any non-empty text; SHA-256 of it seeds the chaotic maps"});
    v.boolean("measure", measure,
              {.label = "Measures",
               .help = "compute the metrics (correlations, Hausdorff distance, key sensitivity): a few more passes"});
  }
};

struct ChaosEncryptResult {
  Mesh mesh;  // the cipher: two header vertices more, normals, UVs and colours dropped
  // key_space_bits, vertices, encrypt_seconds; with `measure`, the adjacent
  // correlations (plain and cipher), the Hausdorff distance, the round trip
  // and the key sensitivity (a key one bit off)
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput as chaos::encrypt does: an empty key, no vertices, a
// non-finite coordinate.
ChaosEncryptResult chaos_encrypt(const Mesh& mesh, const ChaosEncryptParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
