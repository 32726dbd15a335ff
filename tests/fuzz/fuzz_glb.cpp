// The glb mesh reader, as an upload reaches it: the mesh read, then its report.
#include "core/mesh_report.h"
#include "fuzz.h"
#include "io/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  return fuzz::expect_answer([&] {
    const ReadResult r = read_mesh_bytes(fuzz::text(data, size), MeshFormat::glb, "fuzz.glb");
    (void)mesh_report(r.mesh);
  });
}
