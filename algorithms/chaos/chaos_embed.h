// chaos_embed: a message hidden in the low mantissa bits of the float32
// vertex coordinates, at positions a chaotic sequence from the key chooses
// (chaos/embed.h); chaos_extract reads it back.  Teaching and research code.
//
//   Mesh m = read_mesh("elephant.off");
//   ChaosEmbedResult r = chaos_embed(m, {.key = "k", .message = "hello", .bits = 4});
//   write_mesh(r.mesh, "stego.ply");  // PLY, OBJ, OFF or glb keep the message
#pragma once

#include <string>
#include <vector>

#include "chaos/embed.h"
#include "core/mesh.h"
#include "registry/registry.h"

namespace cgview {

enum class ChaosEmbedEncoding { text, base64 };

struct ChaosEmbedParams {
  std::string key = "";
  std::string message = "";
  ChaosEmbedEncoding encoding = ChaosEmbedEncoding::text;
  int bits = 4;
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "any non-empty text; SHA-256 of it seeds the chaotic sequence"});
    v.text("message", message, {.label = "Message", .help = "the text to hide, or a file's bytes in base64"});
    v.choice("encoding", encoding,
             {.label = "Message encoding",
              .help = "text: the message's UTF-8 bytes; base64: the bytes it decodes to (a file: base64 -w0 FILE)",
              .choices = {"text", "base64"}});
    v.integer("bits", bits,
              {.label = "Bits per coordinate",
               .min = 1,
               .max = chaos::kMaxEmbedBits,
               .help = "low mantissa bits used per float32 coordinate: capacity 3 k bits per vertex, each coordinate "
                       "moves by less than 2^(k-23) of its magnitude"});
  }
};

struct ChaosEmbedResult {
  Mesh mesh;  // the stego mesh: positions rounded to float32 and modified
  // message_bytes, capacity_bytes, capacity_bits_per_vertex,
  // bits_per_coordinate, coordinates_modified, the displacements relative to
  // the bounding box's diagonal (rms, max, Hausdorff, the bound) and snr_db
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
    v("metrics", metrics);
  }
};

// Throws InvalidInput as chaos::embed does (an empty key, a message over the
// capacity) and for a base64 message with a character outside base64.
ChaosEmbedResult chaos_embed(const Mesh& mesh, const ChaosEmbedParams& p = {}, Context* ctx = nullptr);

}  // namespace cgview
