// What reading an upload in a child process costs (server/upload_read.h):
// read_upload in the server's own process (the reference: what the server
// did before) against read_upload_in_child (cgview-read --read-upload with
// the jobs' limits: the upload written to a file, a fork and exec, the
// results read back), per sample mesh and format.  Prints a Markdown table
// with the ratio and the cost per upload in milliseconds.
//
//   upload_bench [--repeat N] [--quick] [--only NAME[,NAME...]]
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_util.h"
#include "io/mesh_io.h"
#include "io/samples.h"
#include "upload_read.h"

using namespace cgview;
namespace fs = std::filesystem;

int main(int argc, char** argv) {
  const bench::Options opt = bench::parse_options(argc, argv, "upload_bench");
  const fs::path self = fs::read_symlink("/proc/self/exe");
  server::UploadReader reader;
  reader.program = self.parent_path() / "cgview-read";
  reader.temp_dir = fs::temp_directory_path() / "cgview-upload-bench";
  if (!fs::exists(reader.program)) {
    std::fprintf(stderr, "upload_bench: %s not found (build cgview-read)\n", reader.program.c_str());
    return 1;
  }
  // A small, a middle and the largest sample, and the middle one in other formats.
  std::vector<std::pair<std::string, std::string>> inputs;  // name, bytes
  auto sample = [&](const std::string& file) -> fs::path {
    for (const auto& p : list_samples())
      if (p.filename() == file) return p;
    return {};
  };
  for (const char* f : {"sphere.off", "elephant.off", "armadillo.off", "refined_elephant.off"}) {
    const fs::path p = sample(f);
    if (p.empty()) continue;
    if (opt.quick && std::string(f) == "refined_elephant.off") continue;
    inputs.push_back({f, read_file_bytes(p, std::uint64_t(1) << 30)});
  }
  if (const fs::path p = sample("armadillo.off"); !p.empty()) {
    const Mesh m = read_mesh(p);
    for (const MeshFormat f : {MeshFormat::ply, MeshFormat::stl, MeshFormat::obj, MeshFormat::glb, MeshFormat::drc})
      inputs.push_back({std::string("armadillo.") + to_string(f), write_mesh_bytes(m, f)});
  }
  std::printf("| upload | bytes | in the server's process ms | in a child ms | ratio | cost per upload ms |\n");
  std::printf("|---|---:|---:|---:|---:|---:|\n");
  for (const auto& [name, bytes] : inputs) {
    if (!opt.wants(name)) continue;
    const double in_process =
        bench::best_seconds(opt.repeat, [&] { (void)server::read_upload(name, "", bytes, std::size_t(256) << 20); });
    const double child = bench::best_seconds(
        opt.repeat, [&] { (void)server::read_upload_in_child(reader, name, "", bytes, std::size_t(256) << 20); });
    std::printf("| %s | %zu | %.2f | %.2f | %.2fx | %+.2f |\n", name.c_str(), bytes.size(), in_process * 1e3,
                child * 1e3, child / in_process, (child - in_process) * 1e3);
    std::fflush(stdout);
  }
  std::error_code ec;
  fs::remove_all(reader.temp_dir, ec);
  return 0;
}
