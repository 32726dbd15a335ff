// What the CPU benchmarks share: their options, parsed in one place,
//   --repeat N       best of N runs (default 3)
//   --quick          the small inputs only
//   --only A[,B...]  only the rows (filters, formats) of these names
// the best-of-N timing, and the process's CPU time.
#pragma once

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace cgview::bench {

struct Options {
  int repeat = 3;
  bool quick = false;
  std::vector<std::string> only;
  bool wants(const std::string& name) const {
    return only.empty() || std::find(only.begin(), only.end(), name) != only.end();
  }
};

// The items of a comma-separated list, empty ones dropped.
inline std::vector<std::string> comma_list(const std::string& list) {
  std::vector<std::string> out;
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t comma = std::min(list.find(',', start), list.size());
    if (comma > start) out.push_back(list.substr(start, comma - start));
    start = comma + 1;
  }
  return out;
}

// A benchmark's own option, taken out of argv before parse_options reads
// the common ones: "--name VALUE" its value (with_value), "--name" alone
// an empty string (a flag); nullopt where it is not given.
inline std::optional<std::string> take_option(int& argc, char** argv, const std::string& name, bool with_value) {
  std::optional<std::string> out;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (argv[i] == name && (!with_value || i + 1 < argc)) out = with_value ? std::string(argv[++i]) : std::string();
    else argv[kept++] = argv[i];
  }
  argc = kept;
  return out;
}

// Exits with status 2 and a usage line on anything it does not know
// (--only too, for a benchmark whose rows cannot be chosen: takes_only false).
inline Options parse_options(int argc, char** argv, const char* program, bool takes_only = true) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc) {
      o.repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--quick") {
      o.quick = true;
    } else if (takes_only && a == "--only" && i + 1 < argc) {
      for (std::string& name : comma_list(argv[++i])) o.only.push_back(std::move(name));
    } else {
      std::fprintf(stderr, "usage: %s [--repeat N] [--quick]%s\n", program,
                   takes_only ? " [--only NAME[,NAME...]]" : "");
      std::exit(2);
    }
  }
  return o;
}

// Seconds of the fastest of `repeat` runs of f; setup() runs before each,
// outside the timing.
inline double best_seconds(int repeat, const std::function<void()>& setup, const std::function<void()>& f) {
  double best = 1e300;
  for (int i = 0; i < repeat; ++i) {
    setup();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}
inline double best_seconds(int repeat, const std::function<void()>& f) {
  return best_seconds(
      repeat, [] {}, f);
}

// CPU seconds of the whole process (every thread: llvmpipe's, the ray
// casters', the votes'): steadier than the wall clock on a shared machine.
inline double cpu_seconds() {
  rusage u;
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

}  // namespace cgview::bench
