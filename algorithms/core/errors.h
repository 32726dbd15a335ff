// Exceptions thrown by CGView's algorithms and I/O (after pmp's exceptions.h).
//
// InvalidInput is what the caller got wrong (a malformed file, a bad
// parameter): a server turns it into HTTP 400 and the CLI into a one-line
// message.  IoError is the environment (a file that cannot be opened or
// written).  Library code throws these and never prints or exits.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

namespace cgview {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The input (file content, mesh, parameter) is not acceptable.
class InvalidInput : public Error {
 public:
  using Error::Error;
};

// A file's extension or content names a format CGView does not read or write.
class UnsupportedFormat : public InvalidInput {
 public:
  using InvalidInput::InvalidInput;
};

// A malformed file.  what() reads "FILE: line N: problem" (text formats) or
// "FILE: byte N: problem" (binary formats), so a user can find the spot.
class ParseError : public InvalidInput {
 public:
  ParseError(std::string file, std::string problem, std::optional<std::uint64_t> line,
             std::optional<std::uint64_t> byte_offset);
  const std::string& file() const { return file_; }
  const std::string& problem() const { return problem_; }
  std::optional<std::uint64_t> line() const { return line_; }
  std::optional<std::uint64_t> byte_offset() const { return offset_; }

 private:
  std::string file_, problem_;
  std::optional<std::uint64_t> line_, offset_;
};

// A file that cannot be opened, read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

// A write that found no room (ENOSPC, EDQUOT, SQLite's SQLITE_FULL): a server
// answers 507 and keeps what it had stored.
class DiskFull : public IoError {
 public:
  using IoError::IoError;
};

}  // namespace cgview
