// The server's config file (server/config.h): any bytes as DATA/config.json,
// a ServerConfig or a std::invalid_argument naming the bad key.
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "config.h"
#include "fuzz.h"
#include "server.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  // In memory where there is a tmpfs: rewriting a file on ext4 each input
  // had the target waiting on the disk three quarters of its time.
  static const std::filesystem::path file =
      (std::filesystem::is_directory("/dev/shm") ? std::filesystem::path("/dev/shm")
                                                 : std::filesystem::temp_directory_path()) /
      ("cgview-fuzz-config-" + std::to_string(::getpid()) + ".json");
  if (std::FILE* f = std::fopen(file.c_str(), "wb")) {
    std::fwrite(data, 1, size, f);
    std::fclose(f);
  }
  server::ServerConfig config;
  try {
    server::load_config_file(file, config);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
