// Plugins: from "Build" on the template to its colour map, on the real
// server in its sandbox, as the viewer's code panel does it (save, build
// job, run job, the field's values fetched: the browser then draws them).
// Side by side in the same run: the same algorithm built in (the job
// alone), a rebuild of an unchanged file (the cache), and the compiler
// with and without the precompiled public header.
//
//   build/bin/plugin_bench [--runs 3] [--server build/bin/cgview-server]
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "bench_server.h"
#include "centroid_distance_plugin.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "plugins/plugin.h"

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;
using cgview::bench::call;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

json post(unsigned short port, const std::string& target, const json& body) {
  const auto [status, text] = call(port, "POST", target, body.dump());
  if (status >= 300) throw std::runtime_error(target + ": " + std::to_string(status) + " " + text);
  return json::parse(text);
}

json wait_job(unsigned short port, const std::string& id) {
  for (;;) {
    const json j = json::parse(call(port, "GET", "/api/v1/jobs/" + id).second);
    if (j.value("state", "") != "queued" && j.value("state", "") != "running") return j;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

std::string template_as(const std::string& name, int run) {
  const std::string s = cgview::test::centroid_distance_plugin(CGVIEW_SOURCE_DIR, name);
  return s + "// run " + std::to_string(run) + "\n";  // a new text each run: no cache
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  std::string server = std::string(CGVIEW_BIN_DIR) + "/cgview-server";
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string a = argv[i];
    if (a == "--runs") runs = std::stoi(argv[i + 1]);
    else if (a == "--server") server = argv[i + 1];
  }
  const fs::path data = fs::temp_directory_path() / ("cgview-plugin-bench-" + std::to_string(::getpid()));
  double build_to_field = 0, builtin = 0, cached = 0, compile_pch = 0, compile_plain = 0, unsandboxed = 0;
  {
    cgview::bench::ServerProcess srv(server, data);
    const unsigned short port = srv.port;
    const std::string mesh = cgview::bench::upload(
        port, "elephant.off", cgview::read_file_bytes(*cgview::resolve_mesh_path("elephant"), 1 << 30));
    for (int r = 0; r < runs; ++r) {
      const auto t0 = Clock::now();
      const json p = post(port, "/api/v1/plugins", {{"name", "height"}, {"source", template_as("height", r)}});
      const std::string id = p["id"];
      const json b = wait_job(port, post(port, "/api/v1/plugins/" + id + "/build", json::object())["id"]);
      if (b.value("state", "") != "done") throw std::runtime_error("the build failed: " + b.dump());
      const json j = wait_job(
          port,
          post(port, "/api/v1/jobs", {{"algorithm", "height"}, {"plugin", id}, {"inputs", {{"mesh", mesh}}}})["id"]);
      const auto field =
          call(port, "GET", "/api/v1/jobs/" + j["id"].get<std::string>() + "/artifacts/distance?format=f32");
      if (field.first != 200) throw std::runtime_error("no field: " + j.dump());
      build_to_field += since(t0) / runs;
      // The cache: the same text built again.
      const auto t1 = Clock::now();
      wait_job(port, post(port, "/api/v1/plugins/" + id + "/build", json::object())["id"]);
      cached += since(t1) / runs;
      // The reference: the built-in algorithm the template is, its job alone.
      const auto t2 = Clock::now();
      wait_job(port, post(port, "/api/v1/jobs",
                          {{"algorithm", "centroid_distance"},
                           {"inputs", {{"mesh", mesh}}},
                           {"params", {{"exponent", 1.0 + 0.001 * r}}}})["id"]);
      builtin += since(t2) / runs;
    }
  }
  // What the sandbox costs a job: the built-in algorithm on a server without it.
  {
    cgview::bench::ServerProcess srv(server, data / "off", {"--sandbox", "off"});
    const std::string mesh = cgview::bench::upload(
        srv.port, "elephant.off", cgview::read_file_bytes(*cgview::resolve_mesh_path("elephant"), 1 << 30));
    for (int r = 0; r < runs; ++r) {
      const auto t2 = Clock::now();
      wait_job(srv.port, post(srv.port, "/api/v1/jobs",
                              {{"algorithm", "centroid_distance"},
                               {"inputs", {{"mesh", mesh}}},
                               {"params", {{"exponent", 1.0 + 0.001 * r}}}})["id"]);
      unsandboxed += since(t2) / runs;
    }
  }
  // The compiler alone, with and without the precompiled public header.
  const fs::path dir = data / "compile";
  fs::create_directories(dir);
  cgview::write_file_bytes(dir / "height.cpp", template_as("height", -1));
  cgview::PluginToolchain with = cgview::default_toolchain(), without = with;
  without.pch_dir.clear();
  for (int r = 0; r < runs; ++r) {
    compile_pch += cgview::build_plugin(dir / "height.cpp", dir / "a.so", with).seconds / runs;
    compile_plain += cgview::build_plugin(dir / "height.cpp", dir / "b.so", without).seconds / runs;
  }
  std::error_code ec;
  fs::remove_all(data, ec);
  std::printf("plugin_bench: the template on elephant.off (%d runs, mean), sandboxed server\n", runs);
  std::printf("  Build -> colour map (save, build job, run job, field)  %7.2f s   goal < 5 s\n", build_to_field);
  std::printf("  the built-in algorithm's job alone                     %7.2f s   ratio %.1fx\n", builtin,
              build_to_field / builtin);
  std::printf("  the same job on a server without the sandbox            %7.2f s   sandbox %.2fx\n", unsandboxed,
              builtin / unsandboxed);
  std::printf("  an unchanged file built again (the cache)              %7.2f s\n", cached);
  std::printf("  g++ with the precompiled header                        %7.2f s\n", compile_pch);
  std::printf("  g++ without it                                         %7.2f s   ratio %.2fx\n", compile_plain,
              compile_plain / compile_pch);
  return 0;
}
