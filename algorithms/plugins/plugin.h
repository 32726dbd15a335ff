// Plugins: an algorithm file written against the public header (the
// registry and the core types, registry/registry.h, as the code panel's
// template docs/examples/height.cpp is) compiled into a shared library and
// loaded into a running program, with no rebuild of CGView.
//
//   PluginBuild b = build_plugin("height.cpp", "height.so");   // g++, diagnostics as data
//   if (b.ok) for (auto& name : load_plugin("height.so")) ...  // registered, run as any algorithm
//
// The programs that load plugins (cgview, cgview-worker) export their
// symbols (CMake's ENABLE_EXPORTS), so a plugin links against the registry
// and core types already in them and carries none of its own.  The
// program's symbols come first: a plugin keeps its own functions in an
// anonymous namespace, or a call to one named as one of CGView's may run
// CGView's.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace cgview {

class Context;

// One message of the compiler's, as it said it ("height.cpp:12:5: error: ...").
struct Diagnostic {
  std::string file;
  int line = 0, column = 0;
  std::string severity;  // "error", "warning", "note", "fatal error"
  std::string message;
};

// Where the compiler and the public header are.  The defaults: the compiler
// CGView was built with, the headers of its source tree (or those installed
// beside the program), and the precompiled public header made by the build.
// CGVIEW_PLUGIN_CXX, CGVIEW_PLUGIN_INCLUDE and CGVIEW_PLUGIN_PCH override them.
struct PluginToolchain {
  std::filesystem::path compiler;
  std::filesystem::path include_dir;  // holds registry/registry.h and core/
  std::filesystem::path pch_dir;      // holds cgview/plugin_prelude.h(.gch); empty where there is none (slower builds)
  // The flags every plugin is compiled with; the precompiled header was made with the same.
  std::vector<std::string> flags() const;
  // What makes two builds of one source differ (compiler, flags, headers'
  // place): part of a cache key.
  std::string key() const;
};
PluginToolchain default_toolchain();

struct PluginBuild {
  bool ok = false;                      // the library was written
  std::vector<Diagnostic> diagnostics;  // errors, warnings and notes, in the compiler's order
  std::string output;                   // what the compiler printed, as it printed it
  double seconds = 0;
  // "2 errors; the first: height.cpp:12:5: 'foo' was not declared in this scope"
  std::string summary() const;
};

// Compiles `source` into the shared library `library` (g++ -shared, with the
// precompiled public header where there is one).  Reports progress to `ctx`
// and stops the compiler when it is cancelled (throws Cancelled).  Throws
// IoError when the compiler cannot be started.
PluginBuild build_plugin(const std::filesystem::path& source, const std::filesystem::path& library,
                         const PluginToolchain& toolchain = default_toolchain(), const Context* ctx = nullptr);

// Reads GCC's and Clang's "FILE:LINE:COL: SEVERITY: MESSAGE" lines.
std::vector<Diagnostic> parse_diagnostics(std::string_view compiler_output);

// Loads a plugin library into this process; the names of the algorithms it
// registered.  Throws InvalidInput when it cannot be loaded (dlerror's
// words), registers nothing, or names an algorithm that exists already
// ("the plugin's algorithm 'sdf' has the name of an algorithm CGView has").
std::vector<std::string> load_plugin(const std::filesystem::path& library);

}  // namespace cgview
