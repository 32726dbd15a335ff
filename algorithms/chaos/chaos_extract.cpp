#include "chaos/chaos_extract.h"

#include "chaos/embed.h"

namespace cgview {

ChaosExtractResult chaos_extract(const Mesh& mesh, const ChaosExtractParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  ctx.progress(0, "extracting");
  chaos::ExtractResult x = chaos::extract(mesh, p.key);
  ChaosExtractResult result;
  result.metrics = {{"message_bytes", double(x.message.size())}, {"bits_per_coordinate", double(x.bits)}};
  result.message = Text{std::move(x.message)};
  ctx.progress(1, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(chaos_extract, chaos_extract,
                         {.title = "Extract a hidden message",
                          .description = "Reads back a message hidden by chaos_embed with the same key; fails with "
                                         "'no message found with this key' otherwise.",
                          .area = "chaos"})

}  // namespace cgview
