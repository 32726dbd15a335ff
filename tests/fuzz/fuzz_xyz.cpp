// The point cloud readers of text rows, as an upload reaches them: the first
// byte picks XYZ or PTS, the rest is the file; the cloud read, then its
// report and the Draco point cloud the viewer is streamed.
#include "core/mesh_report.h"
#include "fuzz.h"
#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  if (size == 0) return 0;
  const MeshFormat format = data[0] % 2 == 0 ? MeshFormat::xyz : MeshFormat::pts;
  return fuzz::expect_answer([&] {
    const ReadResult r = read_mesh_bytes(fuzz::text(data + 1, size - 1), format, "fuzz.xyz");
    (void)mesh_report(r.mesh);
    if (r.mesh.num_vertices() <= 4096) (void)write_mesh_bytes(r.mesh, MeshFormat::drc);
  });
}
