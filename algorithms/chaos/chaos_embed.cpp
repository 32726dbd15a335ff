#include "chaos/chaos_embed.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "chaos/measures.h"

namespace cgview {
namespace {

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

}  // namespace

ChaosEmbedResult chaos_embed(const Mesh& mesh, const ChaosEmbedParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0, "embedding");
  const std::string message = p.encoding == ChaosEmbedEncoding::base64 ? from_base64(p.message) : p.message;
  chaos::EmbedResult e = chaos::embed(mesh, p.key, message, p.bits);
  ctx.check_cancelled();
  ctx.progress(0.5, "measuring");
  const double diag = bounding_box(mesh).diagonal();
  const chaos::Displacement d = chaos::displacement(mesh.positions, e.mesh.positions);
  const double h = chaos::hausdorff_vertices(mesh.positions, e.mesh.positions);
  double max_abs = 0;
  for (const Vec3& v : mesh.positions) max_abs = std::max({max_abs, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  ChaosEmbedResult result;
  result.metrics = {
      {"message_bytes", double(message.size())},
      {"capacity_bytes", double(e.capacity_bytes)},
      {"capacity_bits_per_vertex", 3.0 * p.bits},
      {"bits_per_coordinate", double(p.bits)},
      {"coordinates_modified", double(e.slots_used)},
      {"rms_relative", diag > 0 ? d.rms / diag : 0},
      {"max_displacement_relative", diag > 0 ? d.max / diag : 0},
      {"hausdorff_vertices_relative", diag > 0 ? h / diag : 0},
      {"bound_displacement_relative", diag > 0 ? std::sqrt(3.0) * std::ldexp(max_abs, p.bits - 23) / diag : 0},
      {"snr_db", chaos::snr_db(mesh.positions, e.mesh.positions)}};
  result.mesh = std::move(e.mesh);
  result.warnings.push_back(
      "save the mesh as PLY, OBJ, OFF or glb to keep the message: STL, Draco, a text format "
      "with fewer digits or any processing destroys it");
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_embed, chaos_embed,
                         {.title = "Hide a message (chaotic LSB steganography)",
                          .description = "Hides the message in the low mantissa bits of float32 vertex coordinates "
                                         "chosen by a chaotic sequence from the key. Teaching and research code: "
                                         "see docs/CHAOS.md.",
                          .area = "chaos"})

}  // namespace cgview
