// chaos_encrypt / chaos_decrypt: keyed, reversible scrambling of a mesh's
// vertex positions, vertex order and face order by chaotic sequences
// (chaos/encrypt.h).  Teaching and research code, not vetted cryptography.
#include <chrono>
#include <string>

#include "chaos/encrypt.h"
#include "chaos/maps.h"
#include "chaos/measures.h"
#include "registry/registry.h"

namespace cgview {
namespace {

struct KeyParams {
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

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

AlgorithmResult run_encrypt(const Mesh& mesh, const KeyParams& p, Context& ctx) {
  ctx.progress(0, "encrypting");
  const auto t0 = std::chrono::steady_clock::now();
  Mesh cipher = chaos::encrypt(mesh, p.key);
  const double seconds = seconds_since(t0);
  AlgorithmResult result;
  if (mesh.has_normals() || mesh.has_uvs() || mesh.has_colors())
    result.warnings.push_back("normals, UVs and colours are not encrypted and were dropped");
  Metrics m{{"key_space_bits", chaos::key_space_bits},
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
  result.artifacts.push_back({"mesh", std::move(cipher)});
  result.artifacts.push_back({"metrics", std::move(m)});
  ctx.progress(1, "done");
  return result;
}

struct DecryptParams {
  std::string key = "";
  template <class V>
  void describe(V& v) {
    v.text("key", key, {.label = "Key", .help = "the key the mesh was encrypted with"});
  }
};

AlgorithmResult run_decrypt(const Mesh& mesh, const DecryptParams& p, Context& ctx) {
  ctx.progress(0, "decrypting");
  AlgorithmResult result;
  result.artifacts.push_back({"mesh", chaos::decrypt(mesh, p.key)});
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(chaos_encrypt, KeyParams, run_encrypt,
                          {.title = "Chaotic encryption",
                           .description = "Keyed, reversible scrambling of vertex positions (float32, exact), vertex "
                                          "order and face order by chaotic sequences from SHA-256 of the key. "
                                          "Teaching and research code, NOT vetted cryptography: see docs/CHAOS.md.",
                           .area = "chaos",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

CGVIEW_REGISTER_ALGORITHM(chaos_decrypt, DecryptParams, run_decrypt,
                          {.title = "Chaotic decryption",
                           .description = "Inverts chaos_encrypt: with the right key the float32 positions and the "
                                          "faces come back bit for bit; a wrong key gives an unrecognizable mesh.",
                           .area = "chaos",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
