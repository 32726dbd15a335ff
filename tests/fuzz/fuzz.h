// What every fuzz target shares: bytes in, and only what a caller expects
// out.  A parser may answer InvalidInput (ParseError, UnsupportedFormat, ...)
// and nothing else: any other exception escapes to libFuzzer as a crash, as
// do sanitizer reports, leaks, timeouts and allocations past -malloc_limit_mb.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/errors.h"

namespace cgview::fuzz {

inline std::string_view text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs f; InvalidInput is an answer, not a finding.
template <class F>
int expect_answer(F&& f) {
  try {
    f();
  } catch (const InvalidInput&) {
  }
  return 0;
}

}  // namespace cgview::fuzz
