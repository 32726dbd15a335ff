// plugin_build: compiles a user's algorithm file into a plugin library, as a
// job of the worker, so that a build runs where every job runs (in the
// sandbox, under the owner's time, memory and job limits, with progress and
// cancel) and is cached by content as every job is.  Linked into the worker
// only; the server hides it from the algorithm lists and runs it for
// POST /api/v1/plugins/{id}/build (plugin_service.h).
//
// Its results: "library" (the .so), "algorithms" (what the library
// registers, as GET /api/v1/algorithms lists them) and "diagnostics" (the
// compiler's messages as data).  A file that does not build gives the
// diagnostics alone, and a warning that says so.
#include <stdlib.h>

#include <filesystem>
#include <nlohmann/json.hpp>

#include "algorithm_json.h"
#include "io/mesh_io.h"
#include "plugins/plugin.h"
#include "registry/registry.h"

namespace cgview {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Params {
  std::string source;
  std::string file = "plugin.cpp";
  template <class V>
  void describe(V& v) {
    v.text("source", source, {.label = "Source", .help = "the algorithm file's C++ text"});
    v.text("file", file, {.label = "File name", .help = "the name the compiler's messages give it (NAME.cpp)"});
  }
};

std::string file_name(const std::string& f) {
  const bool plain =
      !f.empty() && f.size() <= 64 && f.ends_with(".cpp") && f[0] != '.' &&
      f.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-.") == std::string::npos;
  if (!plain) throw InvalidInput("parameter 'file': a plain name ending in .cpp, such as height.cpp");
  return f;
}

json diagnostics_json(const std::vector<Diagnostic>& ds) {
  json out = json::array();
  for (const auto& d : ds)
    out.push_back(
        {{"file", d.file}, {"line", d.line}, {"column", d.column}, {"severity", d.severity}, {"message", d.message}});
  return out;
}

AlgorithmResult run(const Inputs&, const Params& p, Context& ctx) {
  if (p.source.empty()) throw InvalidInput("parameter 'source': the file is empty");
  const std::string name = file_name(p.file);
  // A directory of its own under /tmp (the sandbox's private one).
  std::string tmpl = (fs::temp_directory_path() / "cgview-build-XXXXXX").string();
  if (!::mkdtemp(tmpl.data())) throw IoError("cannot make a build directory");
  const fs::path dir = tmpl;
  struct Cleanup {
    fs::path d;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(d, ec);
    }
  } cleanup{dir};
  write_file_bytes(dir / name, p.source);
  ctx.progress(0.01, "compiling");
  PluginBuild b = build_plugin(dir / name, dir / "plugin.so", default_toolchain(), &ctx);
  AlgorithmResult r;
  json algos = json::array();
  if (b.ok) {
    ctx.progress(0.95, "loading");
    try {
      for (const std::string& n : load_plugin(dir / "plugin.so")) algos.push_back(protocol::to_json(find_algorithm(n)));
    } catch (const InvalidInput& e) {
      // Built, but not a plugin CGView can use: said as the compiler's errors are.
      b.ok = false;
      b.diagnostics.push_back({name, 0, 0, "error", e.what()});
    }
  }
  r.artifacts.push_back({"diagnostics", Text{diagnostics_json(b.diagnostics).dump()}});
  if (!b.ok) {
    r.warnings.push_back(name + " does not build: " + b.summary());
    return r;
  }
  r.artifacts.push_back({"algorithms", Text{algos.dump()}});
  r.artifacts.push_back({"library", Text{read_file_bytes(dir / "plugin.so", std::uint64_t(1) << 30)}});
  ctx.progress(1.0, "built");
  return r;
}

CGVIEW_REGISTER_ALGORITHM(
    plugin_build, Params, run,
    {.title = "Build a plugin",
     .description = "Compiles an algorithm file into a plugin library (the server's).",
     .area = "system",
     .outputs = {{"diagnostics", OutputKind::text}, {"algorithms", OutputKind::text}, {"library", OutputKind::text}},
     .inputs = {}})

}  // namespace
}  // namespace cgview
