// ASCII case folding, for what is ASCII by definition: file extensions,
// format names, HTTP methods.  One home, so that no file carries its own.
#pragma once

#include <cctype>
#include <string>

namespace cgview {

inline std::string ascii_lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace cgview
