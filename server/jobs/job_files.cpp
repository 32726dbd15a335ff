#include "jobs/job_files.h"

#include <dirent.h>
#include <fcntl.h>
#include <linux/fs.h>
#include <linux/openat2.h>
#include <sys/ioctl.h>
#include <sys/sendfile.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cgview::server {

namespace fs = std::filesystem;

namespace {

struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
};

// Opens `name` beneath `dir` through no link at all.  openat2 says so to
// the kernel for every component; where it is missing (before Linux 5.6)
// only a plain name is taken, opened with O_NOFOLLOW.
int open_beneath(int dir, const std::string& name, int flags) {
  open_how how{};
  how.flags = std::uint64_t(flags | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY);
  how.resolve = RESOLVE_BENEATH | RESOLVE_NO_SYMLINKS | RESOLVE_NO_MAGICLINKS | RESOLVE_NO_XDEV;
  const long fd = ::syscall(SYS_openat2, dir, name.c_str(), &how, sizeof how);
  if (fd >= 0 || errno != ENOSYS) return int(fd);
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..") {
    errno = EXDEV;
    return -1;
  }
  return ::openat(dir, name.c_str(), flags | O_NOFOLLOW | O_CLOEXEC | O_NOCTTY);
}

std::string kind_of(mode_t m) {
  if (S_ISDIR(m)) return "a directory";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m) || S_ISBLK(m)) return "a device";
  if (S_ISSOCK(m)) return "a socket";
  if (S_ISLNK(m)) return "a link";
  return "not a regular file";
}

bool read_all(int fd, std::string& out, std::uint64_t want) {
  out.resize(std::size_t(want));
  std::size_t got = 0;
  while (got < out.size()) {
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) break;
    got += std::size_t(n);
  }
  out.resize(got);
  return true;
}

void walk(int dir, JobDir::Usage& u, std::uint64_t max_names, int depth) {
  const int fd = ::openat(dir, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  DIR* d = ::fdopendir(fd);
  if (!d) {
    ::close(fd);
    return;
  }
  while (const dirent* e = ::readdir(d)) {
    if (std::strcmp(e->d_name, ".") == 0 || std::strcmp(e->d_name, "..") == 0) continue;
    if (++u.names > max_names) break;
    struct stat st {};
    if (::fstatat(::dirfd(d), e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    if (S_ISREG(st.st_mode)) u.bytes += std::uint64_t(st.st_size);
    else if (S_ISDIR(st.st_mode) && depth < 64) {
      const int sub = ::openat(::dirfd(d), e->d_name, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
      if (sub >= 0) {
        walk(sub, u, max_names, depth + 1);
        ::close(sub);
      }
    }
    if (u.names > max_names) break;
  }
  ::closedir(d);
}

}  // namespace

JobDir::JobDir(const fs::path& dir) : fd_(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC)) {}

JobDir::~JobDir() {
  if (fd_ >= 0) ::close(fd_);
}

int JobDir::open_regular(const std::string& name, std::string* why, std::uint64_t* size) const {
  why->clear();
  if (fd_ < 0) return -1;
  // O_NONBLOCK: a FIFO opens at once (and is refused below) instead of
  // waiting for a writer while the server waits on it.
  const int fd = open_beneath(fd_, name, O_RDONLY | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENOENT) return -1;
    if (errno == ELOOP || errno == EXDEV) *why = name + " is a link (a job's links are never followed)";
    else *why = name + " cannot be opened: " + std::strerror(errno);
    return -1;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    *why = name + " is " + kind_of(st.st_mode) + ", not a regular file";
    ::close(fd);
    return -1;
  }
  ::fcntl(fd, F_SETFL, 0);
  *size = std::uint64_t(st.st_size);
  return fd;
}

int JobDir::open_within(const std::string& name, std::uint64_t cap, std::string* why, std::uint64_t* size) const {
  const int fd = open_regular(name, why, size);
  if (fd >= 0 && *size > cap) {
    *why = name + " has " + std::to_string(*size) + " bytes, over the limit of " + std::to_string(cap);
    ::close(fd);
    return -1;
  }
  return fd;
}

std::optional<std::string> JobDir::read(const std::string& name, std::uint64_t cap, std::string* why, bool cut) const {
  std::uint64_t size = 0;
  const Fd fd(open_regular(name, why, &size));
  if (fd.fd < 0) return std::nullopt;
  if (size > cap && !cut) {
    *why = name + " has " + std::to_string(size) + " bytes, over the limit of " + std::to_string(cap);
    return std::nullopt;
  }
  std::string out;
  if (!read_all(fd.fd, out, std::min(size, cap))) {
    *why = name + " cannot be read: " + std::strerror(errno);
    return std::nullopt;
  }
  return out;
}

std::optional<std::uint64_t> JobDir::size_of(const std::string& name, std::string* why) const {
  std::uint64_t size = 0;
  const Fd fd(open_regular(name, why, &size));
  if (fd.fd < 0) return std::nullopt;
  return size;
}

std::optional<std::string> JobDir::read_from(const std::string& name, std::uint64_t offset, std::uint64_t cap,
                                             std::uint64_t* size) const {
  std::string why;
  const Fd fd(open_regular(name, &why, size));
  if (fd.fd < 0) return std::nullopt;
  if (*size <= offset) return std::string();
  if (::lseek(fd.fd, off_t(offset), SEEK_SET) < 0) return std::nullopt;
  std::string out;
  if (!read_all(fd.fd, out, std::min(*size - offset, cap))) return std::nullopt;
  return out;
}

std::optional<std::uint64_t> JobDir::copy(const std::string& name, const fs::path& to, std::uint64_t cap,
                                          std::string* why) const {
  std::uint64_t size = 0;
  const Fd in(open_within(name, cap, why, &size));
  if (in.fd < 0) return std::nullopt;
  const Fd out(::open(to.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644));
  if (out.fd < 0) {
    *why = "cannot write " + to.string() + ": " + std::strerror(errno);
    return std::nullopt;
  }
  // The file may still change size (a straggler on a shared directory):
  // exactly `size` bytes are taken, no more.
  std::uint64_t done = 0;
  while (done < size) {
    ssize_t n = ::copy_file_range(in.fd, nullptr, out.fd, nullptr, std::size_t(size - done), 0);
    if (n < 0 && (errno == EXDEV || errno == ENOSYS || errno == EINVAL || errno == EOPNOTSUPP))
      n = ::sendfile(out.fd, in.fd, nullptr, std::size_t(std::min<std::uint64_t>(size - done, 1 << 30)));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = errno;
      *why = n == 0          ? name + " shrank while it was copied"
             : err == ENOSPC ? std::string("the server's storage is full")
                             : "cannot copy " + name + ": " + std::strerror(err);
      ::unlink(to.c_str());
      errno = err;
      return std::nullopt;
    }
    done += std::uint64_t(n);
  }
  return size;
}

std::optional<std::uint64_t> JobDir::move(const std::string& name, const fs::path& to, std::uint64_t cap,
                                          std::string* why) const {
  std::uint64_t size = 0;
  const Fd in(open_within(name, cap, why, &size));
  if (in.fd < 0) return std::nullopt;
  struct stat opened {};
  // Its one name, as one hard link more would be another way to it.
  if (::fstat(in.fd, &opened) == 0 && opened.st_nlink == 1 && name.find('/') == std::string::npos &&
      ::renameat2(fd_, name.c_str(), AT_FDCWD, to.c_str(), RENAME_NOREPLACE) == 0) {
    // What was renamed is the file checked above (nothing else renames in a
    // run's directory once it ended, but a name is not a file).
    struct stat moved {};
    if (::fstatat(AT_FDCWD, to.c_str(), &moved, AT_SYMLINK_NOFOLLOW) == 0 && moved.st_dev == opened.st_dev &&
        moved.st_ino == opened.st_ino && ::fchown(in.fd, ::geteuid(), ::getegid()) == 0 && ::fchmod(in.fd, 0644) == 0)
      return size;
    *why = "cannot take " + name + " out of the run's directory";
    ::unlink(to.c_str());
    return std::nullopt;
  }
  return copy(name, to, cap, why);
}

JobDir::Usage JobDir::usage(std::uint64_t max_names) const {
  Usage u;
  if (fd_ >= 0) walk(fd_, u, max_names, 0);
  return u;
}

std::uint64_t dir_bytes(const fs::path& dir) { return JobDir(dir).usage().bytes; }

int write_all(int fd, std::string_view bytes) {
  for (std::size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return n < 0 ? errno : EIO;
    done += std::size_t(n);
  }
  return 0;
}

bool spread_subdirectories(const fs::path& dir) {
  const Fd fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC));
  int flags = 0;
  if (fd.fd < 0 || ::ioctl(fd.fd, FS_IOC_GETFLAGS, &flags) != 0) return false;
  if (flags & FS_TOPDIR_FL) return true;
  flags |= FS_TOPDIR_FL;
  return ::ioctl(fd.fd, FS_IOC_SETFLAGS, &flags) == 0;
}

}  // namespace cgview::server
