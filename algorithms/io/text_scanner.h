// Internal: a fast cursor over the text of a mesh file.  Numbers are parsed
// with std::from_chars (no locale, no allocation); the line number of an
// error is counted only when an error is raised.  Lines end with "\n" or
// "\r\n", or with a lone "\r" in a file whose first line so ends (classic
// Mac OS): one kind a file, so that a binary body after a text header is
// never taken for line ends.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/errors.h"

namespace cgview::detail {

class TextScanner {
 public:
  TextScanner(std::string_view text, const std::string& name)
      : begin_(text.data()), p_(text.data()), end_(text.data() + text.size()), name_(name), eol_(line_end_of(text)) {}

  // The character that ends a line of this text: '\r' when its first line
  // ends with a lone '\r', else '\n' (a '\r' before it is then a blank).
  static char line_end_of(std::string_view text) {
    const std::size_t i = text.find_first_of("\r\n");
    return i != std::string_view::npos && text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n') ? '\r'
                                                                                                           : '\n';
  }

  bool at_end() const { return p_ >= end_; }
  const char* pos() const { return p_; }
  const char* end() const { return end_; }
  std::size_t remaining() const { return std::size_t(end_ - p_); }

  // Skips spaces and tabs (and the \r of a \r\n), staying on the line.
  void skip_blanks() {
    while (p_ < end_ && is_blank(*p_, eol_)) ++p_;
  }
  // Skips whitespace across lines, and '#' comments when `comments` is set.
  void skip_space(bool comments = true) {
    for (;;) {
      while (p_ < end_ && is_space(*p_)) ++p_;
      if (comments && p_ < end_ && *p_ == '#') skip_line();
      else return;
    }
  }
  // At the end of a line (or a '#' comment, or the text).
  bool at_eol() {
    skip_blanks();
    return p_ >= end_ || *p_ == eol_ || *p_ == '#';
  }
  // Moves past the next line end.
  void skip_line() {
    const char* nl = static_cast<const char*>(std::memchr(p_, eol_, std::size_t(end_ - p_)));
    p_ = nl ? nl + 1 : end_;
  }
  // The next run of non-space characters on this line.
  std::string_view word() {
    skip_blanks();
    const char* s = p_;
    while (p_ < end_ && !is_space(*p_)) ++p_;
    return {s, std::size_t(p_ - s)};
  }
  bool try_double(double& out) {
    skip_blanks();
    const char* s = p_;
    if (s < end_ && *s == '+') ++s;
    auto [ptr, ec] = std::from_chars(s, end_, out);
    if (ec != std::errc() || (ptr < end_ && !is_space(*ptr) && *ptr != '#')) {
      if (ec == std::errc::result_out_of_range) {  // overflow: keep it as inf, reject later
        out = out_of_range_value(s, ptr);          // underflow ("1e-400"): zero
        p_ = ptr;
        return true;
      }
      return false;
    }
    p_ = ptr;
    return true;
  }
  double need_double(const char* what) {
    double v;
    if (!try_double(v)) fail(std::string("expected ") + what + ", found " + describe_here());
    return v;
  }
  bool try_int(std::int64_t& out) {
    skip_blanks();
    const char* s = p_;
    if (s < end_ && *s == '+') ++s;
    auto [ptr, ec] = std::from_chars(s, end_, out);
    if (ec != std::errc() || (ptr < end_ && !is_space(*ptr) && *ptr != '#')) return false;
    p_ = ptr;
    return true;
  }
  std::int64_t need_int(const char* what) {
    std::int64_t v;
    if (!try_int(v)) fail(std::string("expected ") + what + ", found " + describe_here());
    return v;
  }

  // What is at the cursor, for an error message.
  std::string describe_here() const {
    const char* s = p_;
    while (s < end_ && is_blank(*s, eol_)) ++s;
    if (s >= end_) return "the end of the file";
    if (*s == eol_) return "the end of the line";
    const char* e = s;
    while (e < end_ && !is_space(*e) && e - s < 24) ++e;
    std::string tok(s, e);
    for (char& c : tok)
      if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
    return "'" + tok + "'";
  }
  std::uint64_t line_at(const char* where) const {
    return 1 + std::uint64_t(std::count(begin_, std::min(where, end_), eol_));
  }
  [[noreturn]] void fail(const std::string& problem) const { fail_at(p_, problem); }
  [[noreturn]] void fail_at(const char* where, const std::string& problem) const {
    throw ParseError(name_, problem, line_at(where), std::nullopt);
  }
  void set_pos(const char* p) { p_ = p; }

  // A space within a line whose lines end with `eol`: the other line-end
  // character is one too, or a word() would stop on it without moving.
  static bool is_blank(char c, char eol) {
    return c == ' ' || c == '\t' || c == '\f' || c == '\v' || (c == '\r' && eol == '\n') || (c == '\n' && eol == '\r');
  }
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }

  // The value of a decimal number in [s, e) that from_chars found out of a
  // double's range: +-HUGE_VAL when it overflows, +-0 when it underflows.
  static double out_of_range_value(const char* s, const char* e) {
    const bool negative = s < e && *s == '-';
    std::int64_t lead = 0;  // decimal exponent of the first non-zero digit, before any "e.."
    bool seen_point = false, seen_digit = false;
    const char* p = negative ? s + 1 : s;
    for (; p < e && *p != 'e' && *p != 'E'; ++p) {
      if (*p == '.') {
        seen_point = true;
        continue;
      }
      if (!seen_digit && *p == '0') {
        if (seen_point) --lead;
        continue;
      }
      if (!seen_digit) {
        seen_digit = true;
        if (seen_point) --lead;
        continue;
      }
      if (!seen_point) ++lead;
    }
    std::int64_t exp = 0;
    if (p < e) {
      const char* q = p + 1;
      if (q < e && *q == '+') ++q;
      if (std::from_chars(q, e, exp).ec == std::errc::result_out_of_range) exp = (*q == '-') ? INT32_MIN : INT32_MAX;
      // An exponent near INT64_MAX overflowed lead + exp (the fuzzer found it).
      exp = std::clamp<std::int64_t>(exp, INT32_MIN, INT32_MAX);
    }
    const double v = lead + exp < 0 ? 0.0 : HUGE_VAL;
    return negative ? -v : v;
  }

 private:
  const char* begin_;
  const char* p_;
  const char* end_;
  const std::string& name_;
  char eol_;
};

// OBJ's continuation lines joined: a line that ends with a backslash (blanks
// may follow it) goes on with the next.  Returns `text` itself when nothing is
// continued, else the joined copy kept in `storage`.  Each joined line break
// moves to the end of its joined line, so every later line keeps its number;
// a comment's trailing backslash continues nothing.
inline std::string_view join_continued_lines(std::string_view text, std::string& storage) {
  const char eol = TextScanner::line_end_of(text);
  auto blank = [eol](char c) { return TextScanner::is_blank(c, eol); };
  // Most files have no continuation at all: look before copying.
  bool any = false;
  for (std::size_t b = text.find('\\'); b != std::string_view::npos && !any; b = text.find('\\', b + 1)) {
    std::size_t k = b + 1;
    while (k < text.size() && blank(text[k])) ++k;
    any = k < text.size() && text[k] == eol;
  }
  if (!any) return text;
  storage.clear();
  storage.reserve(text.size());
  std::size_t held = 0;  // line ends joined away, written when the joined line ends
  bool continuing = false, comment = false;
  for (std::size_t pos = 0; pos < text.size();) {
    const std::size_t e = text.find(eol, pos);
    const std::string_view line = text.substr(pos, e == std::string_view::npos ? std::string_view::npos : e - pos);
    if (!continuing) {
      std::size_t first = 0;
      while (first < line.size() && blank(line[first])) ++first;
      comment = first < line.size() && line[first] == '#';
    }
    std::string_view body = line;
    while (!body.empty() && blank(body.back())) body.remove_suffix(1);
    continuing = e != std::string_view::npos && !comment && body.ends_with('\\');
    if (continuing) {
      storage.append(body.substr(0, body.size() - 1));
      storage += ' ';
      ++held;
    } else {
      storage.append(line);
      if (e != std::string_view::npos) storage += eol;
      storage.append(held, eol);
      held = 0;
    }
    pos = e == std::string_view::npos ? text.size() : e + 1;
  }
  storage.append(held, eol);
  return storage;
}

// Refuses a count that the remaining bytes cannot hold, before any allocation.
inline void check_claim(std::uint64_t claimed, std::uint64_t min_bytes_each, std::uint64_t bytes_left, const char* what,
                        const std::string& name, std::uint64_t line) {
  if (min_bytes_each > 0 && claimed > bytes_left / min_bytes_each)
    throw ParseError(name,
                     "the header claims " + std::to_string(claimed) + " " + what + ", but only " +
                         std::to_string(bytes_left) + " bytes follow (at least " + std::to_string(min_bytes_each) +
                         " bytes each)",
                     line, std::nullopt);
}

}  // namespace cgview::detail
