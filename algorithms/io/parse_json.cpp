#include "io/parse_json.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/errors.h"

namespace cgview {

int json_depth(std::string_view text) {
  int depth = 0, deepest = 0;
  bool in_string = false, escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '[' || c == '{') deepest = std::max(deepest, ++depth);
    else if (c == ']' || c == '}') depth = std::max(0, depth - 1);
  }
  return deepest;
}

nlohmann::json parse_json(std::string_view text, const std::string& what, int max_depth) {
  if (const int d = json_depth(text); d > max_depth)
    throw InvalidInput(what + " nests arrays and objects " + std::to_string(d) + " deep; at most " +
                       std::to_string(max_depth) + " are read");
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::out_of_range&) {
    // A number past a double ("6e8618") is out_of_range, not a parse_error.
    throw InvalidInput(what + " holds a number too large for a double");
  }
}

nlohmann::json parse_json_or_discarded(std::string_view text, int max_depth) {
  if (json_depth(text) > max_depth) return nlohmann::json(nlohmann::json::value_t::discarded);
  return nlohmann::json::parse(text, nullptr, false);
}

}  // namespace cgview
