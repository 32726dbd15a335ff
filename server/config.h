// The server's config file (JSON): settings of ServerConfig and the quotas.
//
//   {
//     "server": {"port": 8080, "max_upload_mb": 256, "job_workers": 4},
//     "limits": {"storage_mb": 500, "concurrent_jobs": 4},
//     "users":  {"alice": {"storage_mb": 2000}, "bob": {"concurrent_jobs": null}}
//   }
//
// "server" holds ServerConfig's fields under the names of their command-line
// flags (without "--", '-' as '_'); a flag given on the command line wins.
// "limits" are every user's defaults (not the local user's nor admins'),
// "users" a user's own (null: unlimited).  Every section and key is optional;
// an unknown one is an error naming it.  A new ServerConfig setting is one
// more row in config.cpp's table.
#pragma once

#include <filesystem>
#include <nlohmann/json_fwd.hpp>

#include "server.h"

namespace cgview::server {

// Applies a parsed config document to config; throws std::invalid_argument
// naming the key at fault ("limits.storage_mb: must be a number >= 0 or null").
void apply_config(const nlohmann::json& doc, ServerConfig& config);
// Reads and applies a config file; throws std::invalid_argument naming the
// file (unreadable, not JSON) and the key at fault.
void load_config_file(const std::filesystem::path& file, ServerConfig& config);

}  // namespace cgview::server
