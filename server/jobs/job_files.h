// Reading a job's directory: the files a worker leaves there (its report,
// its output) may be missing or cut short, and the size of the whole
// directory counts against its owner's quota.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace cgview::server {

// The file's bytes; empty when it is missing or unreadable.
std::string read_job_file(const std::filesystem::path& path);
// The bytes of the files under a directory (0 when there is none).
std::uint64_t dir_bytes(const std::filesystem::path& dir);

}  // namespace cgview::server
