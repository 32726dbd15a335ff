#include "plugins/plugin.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <regex>
#include <set>

#include "core/errors.h"
#include "core/shared_library.h"
#include "registry/registry.h"

extern char** environ;

namespace cgview {

namespace fs = std::filesystem;

namespace {

fs::path env_or(const char* name, const fs::path& fallback) {
  const char* v = std::getenv(name);
  return v && *v ? fs::path(v) : fallback;
}

// The directory of this program (for headers installed beside it).
fs::path program_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

}  // namespace

std::vector<std::string> PluginToolchain::flags() const {
  // -O2 as CGView's own algorithms; -fPIC -shared for a library; the public
  // header first, so that its precompiled form is used whatever the file includes.
  std::vector<std::string> f = {"-std=c++20", "-O2", "-fPIC", "-Wall", "-Wextra", "-fdiagnostics-color=never"};
  if (!pch_dir.empty()) f.push_back("-I" + pch_dir.string());
  f.push_back("-I" + include_dir.string());
  return f;
}

std::string PluginToolchain::key() const {
  std::string k = compiler.string();
  for (const auto& f : flags()) k += " " + f;
  return k;
}

PluginToolchain default_toolchain() {
  PluginToolchain t;
  t.compiler = env_or("CGVIEW_PLUGIN_CXX", CGVIEW_PLUGIN_CXX);
  // Installed (the container): headers in ../include/cgview beside bin/.
  const fs::path installed = program_dir().parent_path() / "include" / "cgview";
  std::error_code ec;
  const bool have_installed = fs::exists(installed / "registry" / "registry.h", ec);
  t.include_dir = env_or("CGVIEW_PLUGIN_INCLUDE", have_installed ? installed : fs::path(CGVIEW_PLUGIN_INCLUDE_DIR));
  const fs::path pch = have_installed ? installed.parent_path() / "cgview-pch" : fs::path(CGVIEW_PLUGIN_PCH_DIR);
  t.pch_dir = env_or("CGVIEW_PLUGIN_PCH", pch);
  if (!fs::exists(t.pch_dir / "cgview" / "plugin_prelude.h.gch", ec)) t.pch_dir.clear();
  return t;
}

std::string PluginBuild::summary() const {
  std::size_t errors = 0;
  const Diagnostic* first = nullptr;
  for (const auto& d : diagnostics)
    if (d.severity == "error" || d.severity == "fatal error") {
      if (!first) first = &d;
      ++errors;
    }
  if (ok) return "built in " + std::to_string(int(seconds * 1000)) + " ms";
  if (!first) {
    // A link error or a compiler that died says so in its own words.
    std::string tail = output.size() > 400 ? output.substr(output.size() - 400) : output;
    return "the build failed: " + (tail.empty() ? std::string("the compiler printed nothing") : tail);
  }
  return std::to_string(errors) + (errors == 1 ? " error" : " errors") + "; the first: " + first->file + ":" +
         std::to_string(first->line) + ":" + std::to_string(first->column) + ": " + first->message;
}

std::vector<Diagnostic> parse_diagnostics(std::string_view output) {
  static const std::regex line_re(R"(^(.+?):(\d+):(\d+): (fatal error|error|warning|note): (.*)$)");
  std::vector<Diagnostic> out;
  std::size_t start = 0;
  while (start < output.size()) {
    std::size_t end = output.find('\n', start);
    if (end == std::string_view::npos) end = output.size();
    const std::string line(output.substr(start, end - start));
    std::smatch m;
    if (std::regex_match(line, m, line_re)) out.push_back({m[1], std::stoi(m[2]), std::stoi(m[3]), m[4], m[5]});
    start = end + 1;
  }
  return out;
}

PluginBuild build_plugin(const fs::path& source, const fs::path& library, const PluginToolchain& toolchain,
                         const Context* ctx) {
  std::vector<std::string> args = {toolchain.compiler.string()};
  for (const auto& f : toolchain.flags()) args.push_back(f);
  args.insert(args.end(), {"-include", toolchain.pch_dir.empty() ? "registry/registry.h" : "cgview/plugin_prelude.h",
                           "-shared", "-o", library.string(), source.string()});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw IoError("cannot start the compiler: pipe failed");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, fds[1], STDERR_FILENO);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // Its own process group: cancelling stops cc1plus and as too.
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  pid_t pid = -1;
  const auto t0 = std::chrono::steady_clock::now();
  const int rc = ::posix_spawn(&pid, argv[0], &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  ::close(fds[1]);
  if (rc != 0) {
    ::close(fds[0]);
    throw IoError("cannot start the compiler " + args[0] + ": " + std::strerror(rc));
  }
  PluginBuild b;
  bool cancelled = false;
  for (;;) {
    pollfd p{fds[0], POLLIN, 0};
    ::poll(&p, 1, 100);
    char buf[4096];
    const ssize_t n = p.revents ? ::read(fds[0], buf, sizeof buf) : -1;
    if (n > 0 && b.output.size() < (1u << 20)) b.output.append(buf, std::size_t(n));
    if (n == 0) break;
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (ctx) {
      if (ctx->cancelled()) {
        cancelled = true;
        ::kill(-pid, SIGKILL);
        break;
      }
      // The compiler says nothing of how far it is: time, on a curve that
      // nears the end without reaching it, keeps the bar moving on long builds.
      ctx->progress(0.9 * s / (s + 5.0), "compiling (" + std::to_string(int(s)) + " s)");
    }
  }
  ::close(fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (cancelled) throw Cancelled();
  b.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  b.diagnostics = parse_diagnostics(b.output);
  // The compiler names the file as it was given: name it as the user knows it.
  for (auto& d : b.diagnostics)
    if (d.file == source.string()) d.file = source.filename().string();
  b.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
  if (!b.ok && WIFSIGNALED(status))
    b.output += "\nthe compiler was stopped by signal " + std::to_string(WTERMSIG(status)) + "\n";
  return b;
}

std::vector<std::string> load_plugin(const fs::path& library) {
  std::set<std::string> before;
  for (const auto& [name, a] : algorithms()) before.insert(name);
  std::vector<std::string> clashes;
  detail::set_registration_clashes(&clashes);
  const SharedLibrary lib(fs::absolute(library).c_str());  // its algorithms registered as it opens
  detail::set_registration_clashes(nullptr);
  if (!lib.opened()) throw InvalidInput("cannot load the plugin " + library.filename().string() + ": " + lib.why());
  if (!clashes.empty())
    throw InvalidInput("the plugin's algorithm '" + clashes.front() +
                       "' has the name of an algorithm CGView has: rename it in CGVIEW_REGISTER_FUNCTION");
  std::vector<std::string> added;
  for (const auto& [name, a] : algorithms())
    if (!before.count(name)) added.push_back(name);
  if (added.empty())
    throw InvalidInput("the plugin " + library.filename().string() +
                       " registers no algorithm: end it with CGVIEW_REGISTER_FUNCTION(name, function, {...})");
  return added;
}

}  // namespace cgview
