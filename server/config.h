// cgview-server's settings (settings.h) from its flags and its config file,
// and their listings: --help and docs/DEPLOYMENT.md's tables.
//
// The config file is JSON:
//
//   {
//     "server": {"port": 8080, "max_upload_mb": 256, "job_workers": 4},
//     "limits": {"storage_mb": 500, "concurrent_jobs": 4},
//     "users":  {"alice": {"storage_mb": 2000}, "bob": {"concurrent_jobs": null}}
//   }
//
// "server", "sandbox" and "slurm" hold the settings of settings.h; a flag
// given on the command line wins.  "limits" are every user's defaults (not
// the local user's nor admins'), "users" a user's own (null: unlimited).
// Every section and key is optional; an unknown one is an error naming it.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "server.h"
#include "settings.h"

namespace cgview::server {

// Applies a parsed config document to config; throws std::invalid_argument
// naming the key at fault ("limits.storage_mb: must be a number >= 0 or null").
void apply_config(const nlohmann::json& doc, ServerConfig& config);
// Reads and applies a config file; throws std::invalid_argument naming the
// file (unreadable, not JSON) and the key at fault.
void load_config_file(const std::filesystem::path& file, ServerConfig& config);

// Sets the setting whose flag is `flag` ("--port") from value(), which takes
// the next argument; false where no setting has that flag.  Throws
// std::invalid_argument naming the flag and what it takes
// ("--port needs a number 0..65535, got 'x'").
bool apply_flag(Settings& settings, const std::string& flag, const std::function<std::string()>& value);

// One setting as a person reads it, in the order of Settings::describe.
struct SettingRow {
  std::string section, key;  // key "": a flag only
  std::string flag;          // "": a key of the config file only
  std::string arg;           // "N", "DIR", "auto|required"
  std::string values;        // "1..1048576", "`auto`, `required`"
  std::string default_value;
  std::string help;
  std::string heading;               // --help's heading before it, if any
  std::vector<std::string> choices;  // a choice's names
};
std::vector<SettingRow> list_settings();
// The flags' part of --help.
std::string settings_help();
// A section's settings as the Markdown table of docs/DEPLOYMENT.md.
std::string settings_markdown(const std::string& section);

}  // namespace cgview::server
