// The options every CPU benchmark takes, parsed in one place:
//   --repeat N       best of N runs (default 3)
//   --quick          the small inputs only
//   --only A[,B...]  only the rows (filters, formats) of these names
#pragma once

#include <algorithm>
#include <cstdio>
#include <cstdlib>
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

// Exits with status 2 and a usage line on anything it does not know.
inline Options parse_options(int argc, char** argv, const char* program) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--repeat" && i + 1 < argc) {
      o.repeat = std::max(1, std::atoi(argv[++i]));
    } else if (a == "--quick") {
      o.quick = true;
    } else if (a == "--only" && i + 1 < argc) {
      std::string list = argv[++i];
      for (std::size_t start = 0; start <= list.size();) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        if (comma > start) o.only.push_back(list.substr(start, comma - start));
        start = comma + 1;
      }
    } else {
      std::fprintf(stderr, "usage: %s [--repeat N] [--quick] [--only NAME[,NAME...]]\n", program);
      std::exit(2);
    }
  }
  return o;
}

}  // namespace cgview::bench
