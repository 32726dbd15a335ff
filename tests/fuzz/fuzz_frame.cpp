// The WebSocket binary frame header (protocol/frames.h): any bytes decode to
// a header whose chunk lies inside the frame, or an InvalidInput.
#include <cstdlib>

#include "frames.h"
#include "fuzz.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  return fuzz::expect_answer([&] {
    std::string_view chunk;
    const std::string_view frame = fuzz::text(data, size);
    (void)protocol::decode_frame(frame, &chunk);
    if (chunk.data() < frame.data() || chunk.data() + chunk.size() > frame.data() + frame.size()) std::abort();
  });
}
