// The message of the InvalidInput a call throws, for the suites that check
// how bad parameters are refused (header-only).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/errors.h"

namespace cgview::test {

// The message of the InvalidInput that fn throws ("", and a failure, when it throws none).
template <class Fn>
std::string invalid_input_message(Fn fn) {
  try {
    fn();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InvalidInput thrown";
  return "";
}

}  // namespace cgview::test
