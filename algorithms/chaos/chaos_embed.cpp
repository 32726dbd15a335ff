// chaos_embed / chaos_extract: a message hidden in the low mantissa bits of
// the float32 vertex coordinates, at positions a chaotic sequence from the
// key chooses (chaos/embed.h).  Teaching and research code.
#include <cmath>
#include <string>

#include "chaos/embed.h"
#include "chaos/measures.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct EmbedParams {
  std::string key = "";
  std::string message = "";
  std::string encoding = "text";
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

// RFC 4648 base64 (padding optional, whitespace skipped); throws
// InvalidInput naming 'message'.
std::string from_base64(const std::string& text) {
  std::string out;
  std::uint32_t acc = 0;
  int have = 0;
  for (char c : text) {
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+' || c == '-') v = 62;
    else if (c == '/' || c == '_') v = 63;
    else if (c == '=' || c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    else throw InvalidInput(std::string("parameter 'message': '") + c + "' is not a base64 character");
    acc = acc << 6 | std::uint32_t(v);
    if ((have += 6) >= 8) {
      have -= 8;
      out.push_back(char(acc >> have & 0xFF));
    }
  }
  return out;
}

AlgorithmResult run_embed(const Mesh& mesh, const EmbedParams& p, Context& ctx) {
  ctx.progress(0, "embedding");
  const std::string message = p.encoding == "base64" ? from_base64(p.message) : p.message;
  chaos::EmbedResult e = chaos::embed(mesh, p.key, message, p.bits);
  ctx.check_cancelled();
  ctx.progress(0.5, "measuring");
  const double diag = bounding_box(mesh).diagonal();
  const chaos::Displacement d = chaos::displacement(mesh.positions, e.mesh.positions);
  const double h = chaos::hausdorff_vertices(mesh.positions, e.mesh.positions);
  double max_abs = 0;
  for (const Vec3& v : mesh.positions) max_abs = std::max({max_abs, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  Metrics m{{"message_bytes", double(message.size())},
            {"capacity_bytes", double(e.capacity_bytes)},
            {"capacity_bits_per_vertex", 3.0 * p.bits},
            {"bits_per_coordinate", double(p.bits)},
            {"coordinates_modified", double(e.slots_used)},
            {"rms_relative", diag > 0 ? d.rms / diag : 0},
            {"max_displacement_relative", diag > 0 ? d.max / diag : 0},
            {"hausdorff_vertices_relative", diag > 0 ? h / diag : 0},
            {"bound_displacement_relative", diag > 0 ? std::sqrt(3.0) * std::ldexp(max_abs, p.bits - 23) / diag : 0},
            {"snr_db", chaos::snr_db(mesh.positions, e.mesh.positions)}};
  AlgorithmResult result;
  result.artifacts.push_back({"mesh", std::move(e.mesh)});
  result.artifacts.push_back({"metrics", std::move(m)});
  result.warnings.push_back(
      "save the mesh as PLY, OBJ, OFF or glb to keep the message: STL, Draco, a text format "
      "with fewer digits or any processing destroys it");
  ctx.progress(1, "done");
  return result;
}

struct ExtractParams {
  std::string key = "";
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "the key the message was embedded with"});
  }
};

AlgorithmResult run_extract(const Mesh& mesh, const ExtractParams& p, Context& ctx) {
  ctx.progress(0, "extracting");
  chaos::ExtractResult x = chaos::extract(mesh, p.key);
  AlgorithmResult result;
  Metrics m{{"message_bytes", double(x.message.size())}, {"bits_per_coordinate", double(x.bits)}};
  result.artifacts.push_back({"message", Text{std::move(x.message)}});
  result.artifacts.push_back({"metrics", std::move(m)});
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(chaos_embed, EmbedParams, run_embed,
                          {.title = "Hide a message (chaotic LSB steganography)",
                           .description = "Hides the message in the low mantissa bits of float32 vertex coordinates "
                                          "chosen by a chaotic sequence from the key. Teaching and research code: "
                                          "see docs/CHAOS.md.",
                           .area = "chaos",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

CGVIEW_REGISTER_ALGORITHM(chaos_extract, ExtractParams, run_extract,
                          {.title = "Extract a hidden message",
                           .description = "Reads back a message hidden by chaos_embed with the same key; fails with "
                                          "'no message found with this key' otherwise.",
                           .area = "chaos",
                           .outputs = {{"message", OutputKind::text}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
