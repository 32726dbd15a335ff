// cgview-worker: runs ONE job in its own process, so that a crash, a
// runaway allocation or an endless loop takes down only this job.
//
//   cgview-worker JOB.json      runs the job the file describes:
//     {"algorithm": "hausdorff", "params": {...}, "inputs": {"mesh": "/path/a.off", "reference": "/path/b.ply"}, "out":
//     "/dir"}
//   (an input the algorithm declares as a voxel_grid is a grid file: .nrrd, .binvox, ...)
//   cgview-worker --list        prints every algorithm linked in, as JSON (protocol/algorithm_json)
//
// Progress goes to stdout as lines "progress FRACTION STAGE" (at most ~10 a
// second).  Artifacts go to the output directory in a canonical form:
//   scalar field  NAME.f32 (raw little-endian float32) + NAME.field.json
//                 {"name","location","hint","range":[lo,hi],"count"}
//   mesh          NAME.ply
//   metrics       NAME.json
//   text          NAME.txt (the bytes as they are)
//   animation     NAME.frames (core/animation.h)
//   others        NAME + default_extension (write_artifact)
// and result.json {"artifacts":[{"name","kind","file",...}],"warnings":[...]}.
// Exit status: 0 done; 2 invalid input; 3 out of memory; 4 no room for the
// results (a full disk); 1 any other error
// (the message on stderr and in OUT/error.txt).
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <new>
#include <nlohmann/json.hpp>
#include <string>

#include "algorithm_json.h"
#include "io/mesh_io.h"
#include "registry/artifact_io.h"
#include "registry/registry.h"
#include "voxel/voxel_io.h"

namespace {

using namespace cgview;
using nlohmann::json;
namespace fs = std::filesystem;

void write_text(const fs::path& p, const std::string& s) { write_file_bytes(p, s); }

json save(const Artifact& a, const Mesh& input, const fs::path& out) {
  json entry{{"name", a.name}};
  if (const auto* field = std::get_if<ScalarField>(&a.value)) {
    const auto [lo, hi] = field->range();
    entry["kind"] = "scalar_field";
    entry["file"] = a.name + ".f32";
    entry["location"] = to_string(field->location);
    entry["hint"] = to_string(field->hint);
    entry["range"] = {lo, hi};
    entry["count"] = field->values.size();
    write_file_bytes(out / (a.name + ".f32"), std::string_view(reinterpret_cast<const char*>(field->values.data()),
                                                               field->values.size() * sizeof(float)));
    write_text(out / (a.name + ".field.json"), json{{"name", field->name},
                                                    {"location", entry["location"]},
                                                    {"hint", entry["hint"]},
                                                    {"range", entry["range"]},
                                                    {"count", entry["count"]}}
                                                   .dump());
  } else if (std::holds_alternative<Mesh>(a.value)) {
    entry["kind"] = "mesh";
    entry["file"] = a.name + ".ply";
    write_artifact(a, input, out / (a.name + ".ply"));
  } else if (std::holds_alternative<Metrics>(a.value)) {
    entry["kind"] = "metrics";
    entry["file"] = a.name + ".json";
    write_artifact(a, input, out / (a.name + ".json"));
  } else {
    entry["kind"] = std::holds_alternative<VoxelGrid>(a.value)   ? "voxel_grid"
                    : std::holds_alternative<Text>(a.value)      ? "text"
                    : std::holds_alternative<Animation>(a.value) ? "animation"
                                                                 : "skeleton";
    entry["file"] = a.name + default_extension(a);
    write_artifact(a, input, out / entry["file"].get<std::string>());
  }
  return entry;
}

int run_job(const fs::path& spec_path, fs::path& out) {
  std::ifstream f(spec_path);
  if (!f) throw IoError("cannot read the job file " + spec_path.string());
  const json spec = json::parse(f);
  out = spec.at("out").get<std::string>();
  const Algorithm& algo = find_algorithm(spec.at("algorithm").get<std::string>());
  const auto values = protocol::params_from_json(algo, spec.value("params", json::object()));
  // Every input is a file ("inputs": {"mesh": path, "reference": path}): a
  // stored mesh, or an earlier job's voxel grid or skeleton, as the
  // algorithm declares.
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
        const auto now = Clock::now();
        if (now - last < std::chrono::milliseconds(100) && fraction < 1.0) return;
        last = now;
        std::printf("progress %.4f %.*s\n", fraction, int(stage.size()), stage.data());
        std::fflush(stdout);
      },
      nullptr);
  const AlgorithmResult result = algo.run(inputs, values, ctx);
  json artifacts = json::array();
  for (const Artifact& a : result.artifacts) artifacts.push_back(save(a, mesh, out));
  write_text(out / "result.json", json{{"artifacts", artifacts}, {"warnings", result.warnings}}.dump());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
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
