#include "chaos/chaos_encrypt.h"

#include <chrono>
#include <string>

#include "chaos/encrypt.h"
#include "chaos/maps.h"
#include "chaos/measures.h"

namespace cgview {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

ChaosEncryptResult chaos_encrypt(const Mesh& mesh, const ChaosEncryptParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0, "encrypting");
  const auto t0 = std::chrono::steady_clock::now();
  Mesh cipher = chaos::encrypt(mesh, p.key);
  const double seconds = seconds_since(t0);
  ChaosEncryptResult result;
  if (mesh.has_normals() || mesh.has_uvs() || mesh.has_colors())
    result.warnings.push_back("normals, UVs and colours are not encrypted and were dropped");
  Metrics& m = result.metrics;
  m = {{"key_space_bits", chaos::key_space_bits},
       {"vertices", double(mesh.num_vertices())},
       {"encrypt_seconds", seconds}};
  if (p.measure) {
    ctx.check_cancelled();
    ctx.progress(0.3, "measuring");
    const Mesh plain = chaos::float32_copy(mesh);
    const auto before = chaos::adjacent_correlation(plain.positions);
    const auto after = chaos::adjacent_correlation(cipher.positions);
    const char* axis[] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      m[std::string("correlation_adjacent_") + axis[a] + "_plain"] = before[std::size_t(a)];
      m[std::string("correlation_adjacent_") + axis[a] + "_cipher"] = after[std::size_t(a)];
    }
    const double diag = bounding_box(plain).diagonal();
    const double h = chaos::hausdorff_vertices(plain.positions, cipher.positions);
    m["hausdorff_vertices"] = h;
    m["hausdorff_vertices_relative"] = diag > 0 ? h / diag : 0;
    ctx.check_cancelled();
    ctx.progress(0.7, "key sensitivity");
    const Mesh right = chaos::decrypt(cipher, p.key);
    m["round_trip_exact"] = right.positions == plain.positions && right.faces == plain.faces ? 1 : 0;
    const Mesh wrong = chaos::decrypt(cipher, chaos::flip_one_bit(p.key));
    m["key_sensitivity_changed_coordinates"] = chaos::changed_share(plain.positions, wrong.positions);
    std::size_t faces_changed = 0;
    for (std::size_t f = 0; f < plain.num_faces(); ++f) faces_changed += wrong.faces[f] != plain.faces[f];
    m["key_sensitivity_changed_faces"] = plain.num_faces() ? double(faces_changed) / double(plain.num_faces()) : 0;
    const double hw = chaos::hausdorff_vertices(plain.positions, wrong.positions);
    m["key_sensitivity_hausdorff_relative"] = diag > 0 ? hw / diag : 0;
  }
  result.mesh = std::move(cipher);
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_encrypt, chaos_encrypt,
                         {.title = "Chaotic encryption",
                          .description = "Keyed, reversible scrambling of vertex positions (float32, exact), vertex "
                                         "order and face order by chaotic sequences from SHA-256 of the key. "
                                         "Teaching and research code, NOT vetted cryptography: see docs/CHAOS.md.",
                          .area = "chaos"})

}  // namespace cgview
