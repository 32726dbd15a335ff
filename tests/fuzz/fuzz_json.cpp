// JSON from outside (io/parse_json.h): request bodies, WebSocket messages,
// glTF and side files.  What parses within the depth limit must print, copy
// and compare (each recurses once a level) without exhausting the stack.
#include <nlohmann/json.hpp>

#include "fuzz.h"
#include "io/parse_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  const nlohmann::json j = parse_json_or_discarded(fuzz::text(data, size));
  if (j.is_discarded()) return 0;
  const nlohmann::json copy = j;
  (void)(copy == j);
  (void)copy.dump();
  return 0;
}
