// Parsing JSON that comes from outside (an upload's glTF, a request body, a
// WebSocket message, a side file) with its nesting bounded.
//
// nlohmann::json parses any depth without recursion, but dumping, copying and
// comparing a value recurse once per level: an array nested 100,000 deep (a
// few hundred kB of '[') overflows the stack of whoever prints it in an error
// message.  No format CGView reads needs more than a few levels, so text
// nested deeper than max_depth is refused before it is parsed.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>

namespace cgview {

// Deeper than any glTF, request or side file CGView reads.
inline constexpr int kMaxJsonDepth = 64;

// The deepest nesting of arrays and objects in text (brackets inside strings
// do not count); text need not be valid JSON.
int json_depth(std::string_view text);

// text parsed; throws InvalidInput when it nests deeper than max_depth
// ("WHAT nests arrays and objects N deep; at most M are read") or holds a
// number too large for a double, and nlohmann::json::parse_error when it is
// not JSON.
nlohmann::json parse_json(std::string_view text, const std::string& what, int max_depth = kMaxJsonDepth);

// The same, never throwing: a discarded value (is_discarded()) for text that
// is not JSON or nests too deep.
nlohmann::json parse_json_or_discarded(std::string_view text, int max_depth = kMaxJsonDepth);

}  // namespace cgview
