// cgview-server: the REST and WebSocket server with the browser viewer.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/samples.h"
#include "mesh_service.h"
#include "server.h"

namespace {

const char* kHelp =
    "usage: cgview-server [--host 127.0.0.1] [--port 8080] [--data-dir DIR] [options]\n"
    "\n"
    "Serves the CGView viewer at / and the API under /api/v1 (REST and WebSocket).\n"
    "\n"
    "  --host ADDR          address to listen on (default 127.0.0.1)\n"
    "  --port N             port (default 8080; 0 picks a free one)\n"
    "  --data-dir DIR       where meshes are stored (default ./cgview-data)\n"
    "  --static-dir DIR     the built web client (default: web-client/dist of the source tree)\n"
    "  --samples SET        sample meshes to load at start: default, all or none (default: default)\n"
    "  --max-upload-mb N    largest accepted upload (default 256)\n"
    "  --workers N          worker threads for geometry (default 2)\n"
    "  --gl-platform P      EGL platform for render.png: auto (GPU device, else surfaceless llvmpipe),\n"
    "                       device or surfaceless (default auto; also CGVIEW_GL_PLATFORM)\n"
    "  --ws-chunk-kb N      largest binary WebSocket chunk (default 4096)\n"
    "  --worker PATH        the job worker executable (default: cgview-worker beside this program)\n"
    "  --job-workers N      jobs run at once, each in its own process (default: the number of cores)\n"
    "  --job-timeout-s N    time limit of a job in seconds (default 3600; 0: none)\n"
    "  --job-memory-mb N    address-space limit of a job's process in MB (default 8192; 0: none)\n"
    "  --on-restart WHAT    jobs left queued or running by a previous run: requeue (default) or interrupt\n"
    "  -h, --help           this help\n";

// A few sample meshes of different kinds (the whole set is 143 files).
const std::vector<std::string> kDefaultSamples = {"elephant.off", "bunny00.off", "armadillo.off", "camel.off",
                                                   "man.off",      "kitten.off",  "double-torus-example.off",
                                                   "colored_tetra.ply", "sphere.off"};

}  // namespace

int main(int argc, char** argv) {
  using namespace cgview;
  server::ServerConfig config;
#ifdef CGVIEW_WEB_DIST
  config.static_dir = CGVIEW_WEB_DIST;
#endif
  std::string samples = "default";
  try {
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
          throw std::invalid_argument(a + " needs a number " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + v + "'");
        return n;
      };
      if (a == "-h" || a == "--help") {
        std::fputs(kHelp, stdout);
        return 0;
      } else if (a == "--host") config.host = value();
      else if (a == "--port") config.port = static_cast<unsigned short>(number(0, 65535));
      else if (a == "--data-dir") config.data_dir = value();
      else if (a == "--static-dir") config.static_dir = value();
      else if (a == "--samples") {
        samples = value();
        if (samples != "default" && samples != "all" && samples != "none")
          throw std::invalid_argument("--samples is default, all or none");
      } else if (a == "--max-upload-mb") config.max_upload_bytes = std::size_t(number(1, 1 << 20)) << 20;
      else if (a == "--workers") config.workers = int(number(1, 256));
      else if (a == "--worker") config.jobs.worker = value();
      else if (a == "--gl-platform") config.gl_platform = render::parse_gl_platform(value(), "--gl-platform");
      else if (a == "--job-workers") config.jobs.max_workers = int(number(1, 1024));
      else if (a == "--job-timeout-s") config.jobs.timeout_s = double(number(0, 100000000));
      else if (a == "--job-memory-mb") config.jobs.memory_mb = std::size_t(number(0, 1 << 24));
      else if (a == "--on-restart") {
        const std::string v = value();
        if (v != "requeue" && v != "interrupt") throw std::invalid_argument("--on-restart is requeue or interrupt");
        config.jobs.requeue_on_restart = v == "requeue";
      } else if (a == "--ws-chunk-kb") config.chunk_bytes = std::size_t(number(1, 16 * 1024 - 1)) << 10;
      else throw std::invalid_argument("unknown option " + a);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgview-server: %s (see --help)\n", e.what());
    return 2;
  }
  if (config.jobs.worker.empty()) {
    std::error_code ec;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
    config.jobs.worker = (ec ? std::filesystem::path(argv[0]) : self).parent_path() / "cgview-worker";
  }
  // The renderer says once when only a software renderer is there.
  render::set_render_log([](const std::string& m) { std::fprintf(stderr, "cgview-server: %s\n", m.c_str()); });
  try {
    server::Server srv(config);
    if (samples != "none") {
      std::vector<std::filesystem::path> files;
      for (const auto& f : list_samples())
        if (samples == "all" || std::find(kDefaultSamples.begin(), kDefaultSamples.end(), f.filename()) != kDefaultSamples.end())
          files.push_back(f);
      srv.meshes().import_samples(files, config.max_upload_bytes);
    }
    std::printf("CGView serving http://%s:%u/ (data in %s, %zu meshes)\n", config.host.c_str(), unsigned(srv.port()),
                config.data_dir.c_str(), srv.meshes().store().count());
    std::fflush(stdout);
    srv.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cgview-server: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
