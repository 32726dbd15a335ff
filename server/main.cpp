// cgview-server: the REST and WebSocket server with the browser viewer.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <sys/resource.h>

#include "auth.h"
#include "config.h"
#include "io/samples.h"
#include "mesh_service.h"
#include "server.h"

namespace {

// --help's first part; the settings follow (server/settings.h).
const char* kUsage =
    "usage: cgview-server [--host 127.0.0.1] [--port 8080] [--data-dir DIR] [options]\n"
    "       cgview-server [--data-dir DIR] user add NAME [--role user|teacher|admin] | user list | user revoke NAME\n"
    "\n"
    "Serves the CGView viewer at / and the API under /api/v1 (REST and WebSocket).\n"
    "On a loopback address a single local user needs no token; on any other address, or\n"
    "with --auth required, every request carries \"Authorization: Bearer TOKEN\".\n"
    "\n"
    "  user add NAME        create a user, or give one another token, and print the new token;\n"
    "                       the user's role is exactly what --role says (default user)\n"
    "  user list            the users, their roles, and how many live tokens each has\n"
    "  user revoke NAME     revoke every token of a user, at once, also on a running server\n"
    "  --role ROLE          (user add) user; teacher: also creates courses and enrols students\n"
    "                       (docs/TEACHING.md); admin: sees and changes everyone's data\n"
    "  --admin              (user add) the same as --role admin\n"
    "  -h, --help           this help\n";

// A few sample meshes of different kinds (the whole set is 143 files).
const std::vector<std::string> kDefaultSamples = {"elephant.off",
                                                  "bunny00.off",
                                                  "armadillo.off",
                                                  "camel.off",
                                                  "man.off",
                                                  "kitten.off",
                                                  "double-torus-example.off",
                                                  "colored_tetra.ply",
                                                  "sphere.off"};

// cgview-server user add|list|revoke: on the data directory's store, with or
// without a server running on it.
int user_command(const std::vector<std::string>& args, const std::filesystem::path& data_dir,
                 cgview::server::Role role) {
  using namespace cgview::server;
  const std::string what = args.size() > 1 ? args[1] : "";
  if (!((what == "add" || what == "revoke") && args.size() == 3) && !(what == "list" && args.size() == 2)) {
    std::fprintf(
        stderr,
        "cgview-server: user add NAME [--role user|teacher|admin], user list or user revoke NAME (see --help)\n");
    return 2;
  }
  Store store(data_dir);
  if (what == "add") {
    const std::string token = Auth(store, true).add_user(args[2], role);
    std::printf("%s\n", token.c_str());
    std::fprintf(stderr, "cgview-server: a new token for %s%s; it is shown only once\n", args[2].c_str(),
                 role == Role::admin     ? " (admin)"
                 : role == Role::teacher ? " (teacher)"
                                         : "");
  } else if (what == "list") {
    for (const UserRecord& u : store.list_users())
      std::printf("%-24s %-7s %d token%s  since %s\n", u.name.c_str(), u.role().c_str(), u.tokens,
                  u.tokens == 1 ? "" : "s", u.created.c_str());
  } else {
    if (!store.get_user(args[2])) {
      std::fprintf(stderr, "cgview-server: no user '%s'\n", args[2].c_str());
      return 1;
    }
    const int n = store.revoke_tokens(args[2]);
    std::printf("revoked %d token%s of %s\n", n, n == 1 ? "" : "s", args[2].c_str());
  }
  return 0;
}

// Each connection is a file descriptor, and a login's soft limit (1024 on
// Debian) is far below what the server holds: take the hard limit, as nginx's
// worker_rlimit_nofile and Go's runtime do.  Returns the limit in force.
rlim_t raise_open_file_limit() {
  rlimit l{};
  if (getrlimit(RLIMIT_NOFILE, &l) != 0) return 0;
  if (l.rlim_cur < l.rlim_max) {
    rlimit raised = l;
    raised.rlim_cur = l.rlim_max;
    if (setrlimit(RLIMIT_NOFILE, &raised) == 0) return raised.rlim_cur;
  }
  return l.rlim_cur;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace cgview;
  server::Settings settings;  // the flags' and the config file's (server/settings.h)
  server::ServerConfig& config = settings.server;
#ifdef CGVIEW_WEB_DIST
  config.static_dir = CGVIEW_WEB_DIST;
#endif
  std::vector<std::string> command;  // user add NAME ...
  server::Role role = server::Role::user;
  try {
    // The config file first, so that the flags win over it (user commands need none).
    bool user_command_given = false;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "-h" || a == "--help") {
        std::fputs(kUsage, stdout);
        std::fputs(server::settings_help().c_str(), stdout);
        return 0;
      }
      if ((a == "--config" || a == "--data-dir") && i + 1 < argc)
        (a == "--config" ? settings.config_file : config.data_dir) = argv[++i];
      else if (a == "user") user_command_given = true;
    }
    if (!user_command_given) {
      if (!settings.config_file.empty()) server::load_config_file(settings.config_file, config);
      else if (std::filesystem::exists(config.data_dir / "config.json"))
        server::load_config_file(config.data_dir / "config.json", config);
    }
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      if (server::apply_flag(settings, a, value)) continue;
      if (a == "--admin") role = server::Role::admin;
      else if (a == "--role") {
        const auto r = server::role_from(value());
        if (!r) throw std::invalid_argument("--role is user, teacher or admin");
        role = *r;
      } else if (!a.starts_with("-") && (a == "user" || !command.empty())) command.push_back(a);
      else throw std::invalid_argument("unknown option " + a);
    }
    if (config.tls_cert.empty() != config.tls_key.empty())
      throw std::invalid_argument("--tls-cert and --tls-key go together");
    // Absolute from here on: a sandbox binds and hides paths as they are
    // written, and a job starts elsewhere than the server.
    config.data_dir = std::filesystem::absolute(config.data_dir);
    // Hidden from every sandbox whatever the admin lists: the TLS key and
    // certificate and the config file (the data directory already is).
    for (const std::filesystem::path& secret : {config.tls_key, config.tls_cert, settings.config_file})
      if (!secret.empty()) config.sandbox.hidden.push_back(std::filesystem::absolute(secret));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgview-server: %s (see --help)\n", e.what());
    return 2;
  }
  if (!command.empty()) {
    try {
      return user_command(command, config.data_dir, role);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cgview-server: error: %s\n", e.what());
      return 1;
    }
  }
  // The worker and the reader default to the programs beside this one.
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path bin_dir = (ec ? std::filesystem::path(argv[0]) : self).parent_path();
  if (config.jobs.worker.empty()) config.jobs.worker = bin_dir / "cgview-worker";
  if (config.reader.empty()) config.reader = bin_dir / "cgview-read";
  if (const rlim_t files = raise_open_file_limit(); files < 4096)
    std::fprintf(
        stderr, "cgview-server: at most %llu open files (ulimit -Hn): fewer connections than that are served at once\n",
        static_cast<unsigned long long>(files));
  // The renderer says once when only a software renderer is there.
  render::set_render_log([](const std::string& m) { std::fprintf(stderr, "cgview-server: %s\n", m.c_str()); });
  try {
    server::Server srv(config);
    if (settings.samples != "none") {
      std::vector<std::filesystem::path> files;
      for (const auto& f : list_samples())
        if (settings.samples == "all" ||
            std::find(kDefaultSamples.begin(), kDefaultSamples.end(), f.filename()) != kDefaultSamples.end())
          files.push_back(f);
      srv.meshes().import_samples(files, config.max_upload_bytes);
    }
    std::printf("CGView serving %s://%s:%u/ (data in %s, %zu meshes)\n", srv.tls() ? "https" : "http",
                config.host.c_str(), unsigned(srv.port()), config.data_dir.c_str(), srv.meshes().store().count());
    std::fflush(stdout);
    srv.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgview-server: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
