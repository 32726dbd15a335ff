#include "chaos/chaos_decrypt.h"

#include "chaos/encrypt.h"

namespace cgview {

ChaosDecryptResult chaos_decrypt(const Mesh& mesh, const ChaosDecryptParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0, "decrypting");
  ChaosDecryptResult result;
  result.mesh = chaos::decrypt(mesh, p.key);
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_decrypt, chaos_decrypt,
                         {.title = "Chaotic decryption",
                          .description = "Inverts chaos_encrypt: with the right key the float32 positions and the "
                                         "faces come back bit for bit; a wrong key gives an unrecognizable mesh.",
                          .area = "chaos"})

}  // namespace cgview
