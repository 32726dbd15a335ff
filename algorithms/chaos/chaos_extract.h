// chaos_extract: reads back a message chaos_embed hid in a mesh's float32
// vertex coordinates with the same key (chaos/embed.h).  Teaching and
// research code.
//
//   Mesh m = read_mesh("stego.ply");
//   ChaosExtractResult r = chaos_extract(m, {.key = "k"});
//   std::cout << r.message.bytes;
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

struct ChaosExtractParams {
  std::string key = "";
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "the key the message was embedded with"});
  }
};

struct ChaosExtractResult {
  Text message;     // the bytes as they were embedded
  Metrics metrics;  // message_bytes, bits_per_coordinate
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("message", message);
    v("metrics", metrics);
  }
};

// Throws InvalidInput "no message found with this key" when the key is
// wrong or the mesh holds no message, and for an empty key.
ChaosExtractResult chaos_extract(const Mesh& mesh, const ChaosExtractParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
