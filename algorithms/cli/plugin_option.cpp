#include "plugin_option.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <system_error>
#include <unistd.h>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "plugins/plugin.h"

namespace cgview::cli {

namespace fs = std::filesystem;

namespace {

fs::path cache_dir() {
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "cgview" / "plugins";
  if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "cgview" / "plugins";
  return fs::temp_directory_path() / "cgview-plugins";
}

// FNV-1a: the cache is this user's own, so a 64-bit content hash suffices.
std::string content_hash(std::string_view bytes) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

fs::path built_library(const fs::path& source) {
  const PluginToolchain tc = default_toolchain();
  const std::string text = read_file_bytes(source, 16u << 20);
  // The headers' precompiled form changes with CGView: its size and time key the cache too.
  std::error_code ec;
  std::string pch_stamp;
  if (!tc.pch_dir.empty()) {
    const fs::path gch = tc.pch_dir / "cgview" / "plugin_prelude.h.gch";
    pch_stamp = std::to_string(fs::file_size(gch, ec)) + "/" +
                std::to_string(fs::last_write_time(gch, ec).time_since_epoch().count());
  }
  const fs::path dir = cache_dir();
  fs::create_directories(dir, ec);
  const fs::path lib =
      dir / (source.stem().string() + "-" + content_hash(text + '\0' + tc.key() + '\0' + pch_stamp) + ".so");
  if (fs::exists(lib, ec)) return lib;
  const fs::path tmp = lib.string() + ".tmp" + std::to_string(::getpid());
  const PluginBuild b = build_plugin(source, tmp, tc);
  if (!b.ok) {
    fs::remove(tmp, ec);
    std::fputs(b.output.c_str(), stderr);
    throw InvalidInput(source.filename().string() + " does not build: " + b.summary());
  }
  for (const auto& d : b.diagnostics)
    if (d.severity == "warning")
      std::fprintf(stderr, "cgview: warning: %s:%d:%d: %s\n", d.file.c_str(), d.line, d.column, d.message.c_str());
  fs::rename(tmp, lib);
  return lib;
}

}  // namespace

void take_plugin_options(std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size();) {
    if (args[i] != "--plugin") {
      ++i;
      continue;
    }
    if (i + 1 >= args.size()) throw InvalidInput("--plugin needs a file (an algorithm's .cpp, or a built .so)");
    const fs::path file = args[i + 1];
    args.erase(args.begin() + long(i), args.begin() + long(i) + 2);
    if (!fs::exists(file)) throw InvalidInput("no plugin file " + file.string());
    load_plugin(file.extension() == ".so" ? file : built_library(file));
  }
}

}  // namespace cgview::cli
