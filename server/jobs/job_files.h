// Reading what a job leaves behind.  A job's directory is hostile input:
// the worker, a user's plugin or a broken node may have put anything there
// (a link to the server's database, a FIFO, /dev/zero, a file of
// terabytes, a million names).  So the server opens a file there only
// beneath the directory, through no link (openat2 with RESOLVE_BENEATH and
// RESOLVE_NO_SYMLINKS where the kernel has it, else one name with
// O_NOFOLLOW), without blocking (O_NONBLOCK: a FIFO opens at once and is
// then refused), takes it only when it is a regular file, and reads it up
// to a cap.  The caps are stated in docs/DEPLOYMENT.md ("What a job can
// see").
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace cgview::server {

// The caps on what the server reads of a job's files.
inline constexpr std::uint64_t kMaxReportBytes = 64 << 10;     // error.txt, stderr.txt, worker.exit: the first 64 KiB
inline constexpr std::uint64_t kMaxResultJsonBytes = 4 << 20;  // result.json: 4 MiB, else the job fails
inline constexpr std::size_t kMaxArtifacts = 256;              // entries of result.json's list
inline constexpr std::uint64_t kMaxSideFileBytes = 1 << 20;    // an artifact's side file (a field's .field.json)

// A directory a job could write, opened once (no link followed on the way
// down from its last component).
class JobDir {
 public:
  explicit JobDir(const std::filesystem::path& dir);
  ~JobDir();
  JobDir(const JobDir&) = delete;
  JobDir& operator=(const JobDir&) = delete;
  // A file's bytes, read to at most `cap` (the rest cut off when `cut`,
  // else an error).  nullopt with *why set when it cannot be taken ("is a
  // link", "is not a regular file", "has N bytes, over the limit of M");
  // *why left empty when the file is simply missing.
  std::optional<std::string> read(const std::string& name, std::uint64_t cap, std::string* why, bool cut = false) const;
  // The size of the regular file `name`; nullopt as read says.
  std::optional<std::uint64_t> size_of(const std::string& name, std::string* why) const;
  // Like read, from byte `offset` on (a growing output file).
  std::optional<std::string> read_from(const std::string& name, std::uint64_t offset, std::uint64_t cap,
                                       std::uint64_t* size) const;
  // Copies the file to `to` (a new file in a directory only the server
  // writes), at most `cap` bytes; its size, or nullopt with *why set as read does.
  std::optional<std::uint64_t> copy(const std::string& name, const std::filesystem::path& to, std::uint64_t cap,
                                    std::string* why) const;
  // The same file moved there instead (a rename: no new file, no bytes
  // copied), made the server's (its owner, mode 0644), where nothing can
  // write it any more (a sandboxed run, ended) and it is the file's only
  // name; else, or where it cannot be renamed there, copied.
  std::optional<std::uint64_t> move(const std::string& name, const std::filesystem::path& to, std::uint64_t cap,
                                    std::string* why) const;

  // The bytes and the names under the directory, links and all counted as
  // names and none followed; the walk stops past `max_names`.
  struct Usage {
    std::uint64_t bytes = 0, names = 0;
  };
  Usage usage(std::uint64_t max_names = ~std::uint64_t(0)) const;

 private:
  // An open descriptor of the regular file `name` beneath the directory,
  // or -1 with *why set (empty when missing).
  int open_regular(const std::string& name, std::string* why, std::uint64_t* size) const;
  // The same, refused (*why set) when over `cap` bytes.
  int open_within(const std::string& name, std::uint64_t cap, std::string* why, std::uint64_t* size) const;
  int fd_ = -1;
};

// Marks `dir` as the top of directory trees for ext4's allocator (chattr
// +T): each directory made in it then goes to a block group of its own
// choosing, with the files made in it, instead of the group of `dir`.  The
// runs' directories are made and removed by the thousand, and ext4 without
// a journal skips, for each new inode, every inode of its group freed in
// the last minutes: in one group with the rest of /tmp, that scan took
// more CPU than a job's sandbox.  False where the file system has no such
// flag (nothing changes).
bool spread_subdirectories(const std::filesystem::path& dir);

// `bytes` written whole to `fd` (again after a signal): 0, or the errno
// that stopped it (EIO where the file took no more).
int write_all(int fd, std::string_view bytes);

// The bytes of the files under a directory, no link followed (0 when there is none).
std::uint64_t dir_bytes(const std::filesystem::path& dir);

}  // namespace cgview::server
