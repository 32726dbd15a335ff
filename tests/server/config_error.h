// What apply_config says of a config file's JSON: its exception's text, or ""
// when it takes it (header-only, for the tests of the config file).
#pragma once

#include <exception>
#include <nlohmann/json.hpp>
#include <string>

#include "config.h"

namespace cgview::server {

inline std::string config_error(const nlohmann::json& doc) {
  ServerConfig c;
  try {
    apply_config(doc, c);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace cgview::server
