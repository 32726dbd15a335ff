#include "core/errors.h"

namespace cgview {
namespace {
std::string format_parse_error(const std::string& file, const std::string& problem, std::optional<std::uint64_t> line,
                               std::optional<std::uint64_t> offset) {
  std::string s = file + ": ";
  if (line) s += "line " + std::to_string(*line) + ": ";
  else if (offset) s += "byte " + std::to_string(*offset) + ": ";
  return s + problem;
}
}  // namespace

ParseError::ParseError(std::string file, std::string problem, std::optional<std::uint64_t> line,
                       std::optional<std::uint64_t> byte_offset)
    : InvalidInput(format_parse_error(file, problem, line, byte_offset)),
      file_(std::move(file)),
      problem_(std::move(problem)),
      line_(line),
      offset_(byte_offset) {}

}  // namespace cgview
