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

const char* kHelp =
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
    "  --auth MODE          auto (default: tokens unless the address is loopback) or required\n"
    "  --config FILE        settings and per-user quotas, JSON (default: DATA-DIR/config.json if\n"
    "                       there); flags given here win over the file (docs/DEPLOYMENT.md, Quotas)\n"
    "\n"
    "  --host ADDR          address to listen on (default 127.0.0.1)\n"
    "  --port N             port (default 8080; 0 picks a free one)\n"
    "  --data-dir DIR       where meshes are stored (default ./cgview-data)\n"
    "  --static-dir DIR     the built web client (default: web-client/dist of the source tree)\n"
    "  --samples SET        sample meshes to load at start: default, all or none (default: default)\n"
    "  --max-upload-mb N    largest accepted upload (default 256)\n"
    "\n"
    "Limits (docs/DEPLOYMENT.md; over a limit: 431, 413, 408, 429 or 503 and the connection closed):\n"
    "  --max-header-kb N    request line and headers (default 64)\n"
    "  --max-ws-message-kb N  a WebSocket message from a client (default 1024)\n"
    "  --request-timeout-s N  a request's headers must arrive within N s of its first byte (default 30)\n"
    "  --min-body-rate-kb N   then its body at N KB/s on average (default 64)\n"
    "  --idle-timeout-s N   a keep-alive connection with no request for N s is closed (default 60)\n"
    "  --ws-idle-timeout-s N  a silent WebSocket is pinged at N/2 s, closed at N s without a pong (default 60)\n"
    "  --ws-auth-timeout-s N  a WebSocket not authenticated in N s is closed where tokens are needed (default 5)\n"
    "  --max-connections-per-ip N  open connections of one address (0: no cap; default 1024 off loopback)\n"
    "  --rate-limit R[/B]   requests per second per token, or per address without one (not the\n"
    "                       loopback local user), in bursts of B (default 50/200; 0: none)\n"
    "  --tls-cert FILE      serve https:// and wss:// with this PEM certificate chain ...\n"
    "  --tls-key FILE       ... and its PEM private key (default: plain HTTP; or a proxy, docker/Caddyfile)\n"
    "\n"
    "  --workers N          worker threads for geometry (default 2)\n"
    "  --gl-platform P      EGL platform for render.png: auto (GPU device, else surfaceless llvmpipe),\n"
    "                       device or surfaceless (default auto; also CGVIEW_GL_PLATFORM)\n"
    "  --ws-chunk-kb N      largest binary WebSocket chunk (default 4096)\n"
    "  --preview-faces N    meshes with more faces get a decimated preview first (default 200000; 0: none)\n"
    "  --preview-target N   the preview's most faces (default 80000)\n"
    "  --worker PATH        the job worker executable (default: cgview-worker beside this program)\n"
    "  --job-workers N      jobs run at once, each in its own process (default: the number of cores)\n"
    "  --job-timeout-s N    time limit of a job in seconds (default 3600; 0: none)\n"
    "  --job-memory-mb N    address-space limit of a job's process in MB (default 8192; 0: none);\n"
    "                       also of the process that reads each upload (over it: 413)\n"
    "  --reader PATH        the upload reader executable (default: cgview-read beside this program)\n"
    "  --upload-timeout-s N  time limit of reading one upload, in its own process (default 120; over: 413)\n"
    "  --on-restart WHAT    jobs left queued or running by a previous run: requeue (default) or interrupt\n"
    "  --executor WHERE     where jobs run: local (this machine, default) or slurm (the config's slurm section)\n"
    "  --job-cpus N         CPUs of a job (Slurm's --cpus-per-task; default 1)\n"
    "  --sandbox MODE       each job's worker in bubblewrap: auto (where it starts, default), required, off\n"
    "  --plugin-dir DIR     the lab's plugins (*.cpp) for every user, rebuilt when a file changes\n"
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
  server::ServerConfig config;
#ifdef CGVIEW_WEB_DIST
  config.static_dir = CGVIEW_WEB_DIST;
#endif
  std::string samples = "default";
  std::vector<std::string> command;  // user add NAME ...
  server::Role role = server::Role::user;
  try {
    // The config file first, so that the flags win over it (user commands need none).
    std::filesystem::path config_file;
    bool user_command_given = false;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if ((a == "--config" || a == "--data-dir") && i + 1 < argc)
        (a == "--config" ? config_file : config.data_dir) = argv[++i];
      else if (a == "user") user_command_given = true;
    }
    if (!user_command_given) {
      if (!config_file.empty()) server::load_config_file(config_file, config);
      else if (std::filesystem::exists(config.data_dir / "config.json"))
        server::load_config_file(config.data_dir / "config.json", config);
    }
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
        return argv[++i];
      };
      auto number = [&](long lo, long hi) {
        const std::string v = value();
        char* end = nullptr;
        const long n = std::strtol(v.c_str(), &end, 10);
        if (v.empty() || *end || n < lo || n > hi)
          throw std::invalid_argument(a + " needs a number " + std::to_string(lo) + ".." + std::to_string(hi) +
                                      ", got '" + v + "'");
        return n;
      };
      if (a == "-h" || a == "--help") {
        std::fputs(kHelp, stdout);
        return 0;
      } else if (a == "--host") config.host = value();
      else if (a == "--port") config.port = static_cast<unsigned short>(number(0, 65535));
      else if (a == "--data-dir") config.data_dir = value();
      else if (a == "--config") (void)value();  // read above
      else if (a == "--static-dir") config.static_dir = value();
      else if (a == "--samples") {
        samples = value();
        if (samples != "default" && samples != "all" && samples != "none")
          throw std::invalid_argument("--samples is default, all or none");
      } else if (a == "--max-upload-mb") config.max_upload_bytes = std::size_t(number(1, 1 << 20)) << 20;
      else if (a == "--max-header-kb") config.max_header_bytes = std::size_t(number(1, 1 << 20)) << 10;
      else if (a == "--max-ws-message-kb") config.max_ws_message_bytes = std::size_t(number(1, 1 << 20)) << 10;
      else if (a == "--request-timeout-s") config.request_timeout_s = double(number(1, 86400));
      else if (a == "--min-body-rate-kb") config.min_body_rate = double(number(1, 1 << 20)) * 1024;
      else if (a == "--idle-timeout-s") config.idle_timeout_s = double(number(1, 86400));
      else if (a == "--ws-idle-timeout-s") config.ws_idle_timeout_s = double(number(2, 86400));
      else if (a == "--ws-auth-timeout-s") config.ws_auth_timeout_s = double(number(1, 3600));
      else if (a == "--max-connections-per-ip") config.max_connections_per_ip = int(number(0, 1 << 20));
      else if (a == "--rate-limit") {
        const std::string v = value();
        char* end = nullptr;
        config.rate_per_s = std::strtod(v.c_str(), &end);
        config.rate_burst = *end == '/' ? std::strtod(end + 1, &end) : std::max(1.0, config.rate_per_s * 4);
        if (v.empty() || *end || !(config.rate_per_s >= 0) || !(config.rate_burst >= 1) || config.rate_per_s > 1e9 ||
            config.rate_burst > 1e9)
          throw std::invalid_argument("--rate-limit is RATE or RATE/BURST (requests per second, burst >= 1), got '" +
                                      v + "'");
      } else if (a == "--tls-cert") config.tls_cert = value();
      else if (a == "--tls-key") config.tls_key = value();
      else if (a == "--workers") config.workers = int(number(1, 256));
      else if (a == "--worker") config.jobs.worker = value();
      else if (a == "--plugin-dir") config.plugin_dir = value();
      else if (a == "--sandbox") {
        config.sandbox.mode = value();
        if (config.sandbox.mode != "auto" && config.sandbox.mode != "required" && config.sandbox.mode != "off")
          throw std::invalid_argument("--sandbox is auto, required or off");
      } else if (a == "--reader") config.reader = value();
      else if (a == "--gl-platform") config.gl_platform = render::parse_gl_platform(value(), "--gl-platform");
      else if (a == "--job-workers") config.jobs.max_workers = int(number(1, 1024));
      else if (a == "--job-timeout-s") config.jobs.timeout_s = double(number(0, 100000000));
      else if (a == "--job-memory-mb") config.jobs.memory_mb = std::size_t(number(0, 1 << 24));
      else if (a == "--job-cpus") config.jobs.cpus = int(number(1, 1024));
      else if (a == "--executor") {
        const std::string v = value();
        if (v != "local" && v != "slurm") throw std::invalid_argument("--executor is local or slurm");
        config.jobs.executor = v;
      } else if (a == "--upload-timeout-s") config.upload_timeout_s = double(number(1, 86400));
      else if (a == "--on-restart") {
        const std::string v = value();
        if (v != "requeue" && v != "interrupt") throw std::invalid_argument("--on-restart is requeue or interrupt");
        config.jobs.requeue_on_restart = v == "requeue";
      } else if (a == "--ws-chunk-kb") config.chunk_bytes = std::size_t(number(1, 16 * 1024 - 1)) << 10;
      else if (a == "--preview-faces") config.preview.threshold_faces = std::size_t(number(0, 1LL << 40));
      else if (a == "--preview-target") config.preview.target_faces = std::size_t(number(1, 1LL << 40));
      else if (a == "--auth") {
        const std::string v = value();
        if (v != "auto" && v != "required") throw std::invalid_argument("--auth is auto or required");
        config.auth_required = v == "required";
      } else if (a == "--admin") role = server::Role::admin;
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
    for (const std::filesystem::path& secret : {config.tls_key, config.tls_cert, config_file})
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
    if (samples != "none") {
      std::vector<std::filesystem::path> files;
      for (const auto& f : list_samples())
        if (samples == "all" ||
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
