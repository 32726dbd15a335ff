// cgview-worker: runs ONE job in its own process, so that a crash, a
// runaway allocation or an endless loop takes down only this job.
//
//   cgview-worker JOB.json      runs the job the file describes:
//     {"algorithm": "hausdorff", "params": {...}, "inputs": {"mesh": "/path/a.off", "reference": "/path/b.ply"}, "out":
//     "/dir"}
//   (an input the algorithm declares as a voxel_grid is a grid file: .nrrd, .binvox, ...)
//   ("plugin": "/path/lib.so" loads a user's algorithm library first: plugins/plugin.h)
//   cgview-worker --list        prints every algorithm linked in, as JSON (protocol/algorithm_json)
//   (CGVIEW_JOB_USER=ID, set by a root server's sandbox: it drops to that user first, sandbox.h)
//
// A worker whose stdin is a pipe was started ahead of its job (the local
// executor's pre-started worker, local_executor.h): it loads, says so on
// stdout ("progress 0 ready"), waits for the pipe to close, and only then
// reads JOB.json, which the server has written meanwhile.
//
// Progress goes to stdout as lines "progress FRACTION STAGE" (at most ~10 a
// second), and nothing else: what the algorithm prints there goes to stderr.
// Each artifact is stored in the output directory by its kind's codec
// (artifacts/artifact_codec.h: a field as NAME.f32, a mesh as NAME.ply, ...),
// and result.json lists them: {"artifacts":[{"name","kind","file","bytes",
// ...}],"warnings":[...]} ("bytes": each file's size as written, which the
// server checks).
// Exit status: 0 done; 2 invalid input; 3 out of memory; 4 no room for the
// results (a full disk); 1 any other error
// (the message on stderr and in OUT/error.txt).
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "algorithm_json.h"
#include "child_process.h"
#include "io/mesh_io.h"
#include "jobs/executor.h"
#include "artifacts/artifact_codec.h"
#include "registry/artifact_io.h"
#include "plugins/plugin.h"
#include "registry/registry.h"
#include "sandbox.h"

namespace {

using namespace cgview;
using nlohmann::json;
namespace fs = std::filesystem;

// The progress pipe is the worker's own: from here on, what an algorithm or
// a library prints to stdout goes to stderr, so that only progress lines
// reach the pipe (the server fails a job whose pipe carries anything else).
std::FILE* take_progress_pipe() {
  const int fd = ::dup(STDOUT_FILENO);
  std::FILE* pipe = fd >= 0 ? ::fdopen(fd, "w") : nullptr;
  if (!pipe || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) throw IoError("cannot set up the progress pipe");
  return pipe;
}

// A stage on one line of printable text, however the algorithm named it.
std::string one_line(std::string_view stage) {
  std::string s(stage.substr(0, 200));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  return s;
}

// A pre-started worker's wait for its job: it says it is ready, then waits
// for the end of its stdin pipe.
void wait_for_the_job() {
  struct stat st {};
  if (::fstat(STDIN_FILENO, &st) != 0 || !S_ISFIFO(st.st_mode)) return;
  if (::write(STDOUT_FILENO, server::kWorkerReady.data(), server::kWorkerReady.size()) < 0)
    throw IoError("cannot write on the progress pipe");
  char buf[256];
  for (ssize_t n; (n = ::read(STDIN_FILENO, buf, sizeof buf)) != 0;)
    if (n < 0 && errno != EINTR) return;
}

int run_job(const fs::path& spec_path, fs::path& out) {
  wait_for_the_job();
  std::FILE* const progress = take_progress_pipe();
  std::ifstream f(spec_path);
  if (!f) throw IoError("cannot read the job file " + spec_path.string());
  const json spec = json::parse(f);
  out = spec.at("out").get<std::string>();
  if (spec.contains("plugin")) load_plugin(spec["plugin"].get<std::string>());
  const Algorithm& algo = find_algorithm(spec.at("algorithm").get<std::string>());
  const auto values = protocol::params_from_json(algo, spec.value("params", json::object()));
  // Every input is a file ("inputs": {"mesh": path, "reference": path}): a
  // stored mesh, or an earlier job's voxel grid, skeleton or points (a
  // cloud's file, or a mesh's: its vertices), as the algorithm declares.
  InputFiles files;
  const json paths = spec.value("inputs", json::object());
  for (const InputSpec& in : algo.info.inputs)
    if (paths.contains(in.name)) files.read(in, paths.at(in.name).get<std::string>());
  const Inputs& inputs = files.inputs();
  const Mesh& mesh = files.primary_mesh();
  using Clock = std::chrono::steady_clock;
  Clock::time_point last{};
  Context ctx(
      [&](double fraction, std::string_view stage) {
        if (!std::isfinite(fraction)) return;
        const auto now = Clock::now();
        if (now - last < std::chrono::milliseconds(100) && fraction < 1.0) return;
        last = now;
        std::fprintf(progress, "progress %.4f %s\n", fraction, one_line(stage).c_str());
        std::fflush(progress);
      },
      nullptr);
  const AlgorithmResult result = algo.run(inputs, values, ctx);
  json artifacts = json::array();
  for (const Artifact& a : result.artifacts) artifacts.push_back(artifact_codec(kind_of(a.value)).store(a, mesh, out));
  write_file_bytes(out / "result.json", json{{"artifacts", artifacts}, {"warnings", result.warnings}}.dump());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // A root server's sandbox starts it as root, for it to drop to the job's
  // user here, before anything of the job is read or loaded (sandbox.h).
  if (const char* user = std::getenv(server::kJobUserVariable)) {
    try {
      server::drop_to_job_user(std::stol(user));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cannot drop to the job's user %s: %s\n", user, e.what());
      return 1;
    }
    ::unsetenv(server::kJobUserVariable);
  }
  if (argc == 2 && std::string(argv[1]) == "--list") {
    json list = json::array();
    for (const auto& [name, a] : algorithms()) list.push_back(protocol::to_json(a));
    std::printf("%s\n", list.dump().c_str());
    return 0;
  }
  if (argc != 2) {
    std::fputs("usage: cgview-worker JOB.json | --list\n", stderr);
    return 64;
  }
  cgview::server::end_with_server();  // a worker whose server is gone ends, sandbox and all
  fs::path out;
  auto fail = [&](int code, const std::string& msg) {
    std::fprintf(stderr, "%s\n", msg.c_str());
    if (!out.empty()) {
      std::ofstream e(out / "error.txt");
      e << msg;
    }
    return code;
  };
  try {
    return run_job(argv[1], out);
  } catch (const std::bad_alloc&) {
    return fail(3, "out of memory");
  } catch (const DiskFull& e) {
    return fail(4, e.what());  // the status says it: error.txt may not fit either
  } catch (const InvalidInput& e) {
    return fail(2, e.what());
  } catch (const std::exception& e) {
    return fail(1, e.what());
  }
}
