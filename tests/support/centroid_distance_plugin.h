// The built-in centroid_distance as a plugin file, for the tests and the
// benchmark of plugins, which check that a plugin gives what the built-in
// algorithm it copies gives (header-only: the benchmark links no test
// support).  A plugin is one file against the public header, so the
// algorithm's header (algorithms/examples/centroid_distance.h) is pasted
// over its .cpp's include of it.  Its function is renamed with the
// registered name: the programs that load plugins export their symbols, and
// a call to cgview::centroid_distance in the plugin would reach the built-in
// one, not the plugin's own copy.  The field's name (a string) is kept, so
// that the plugin's files equal the built-in's.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace cgview::test {

inline std::string centroid_distance_plugin(const std::filesystem::path& source_dir, const std::string& name) {
  const auto read = [&](const char* file) {
    std::ifstream in(source_dir / "algorithms" / "examples" / file, std::ios::binary);
    if (!in) throw std::runtime_error(std::string("cannot read algorithms/examples/") + file);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
  };
  std::string header = read("centroid_distance.h");
  const std::string once = "#pragma once\n";
  if (const auto at = header.find(once); at != std::string::npos) header.erase(at, once.size());
  std::string s = read("centroid_distance.cpp");
  const std::string include = "#include \"examples/centroid_distance.h\"\n";
  const auto at = s.find(include);
  if (at == std::string::npos) throw std::runtime_error("centroid_distance.cpp no longer includes its header");
  s.replace(at, include.size(), header);
  const std::string word = "centroid_distance";
  std::string out;
  std::size_t from = 0;
  for (std::size_t k; (k = s.find(word, from)) != std::string::npos; from = k + word.size())
    out += s.substr(from, k - from) + (k > 0 && s[k - 1] == '"' ? word : name);
  return out + s.substr(from);
}

}  // namespace cgview::test
