// An OBJ's materials: the MTL parser, and the OBJ's usemtl and mtllib lines
// (the input read both as an MTL and as an OBJ).
#include "fuzz.h"
#include "io/materials.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  return fuzz::expect_answer([&] {
    (void)parse_mtl(fuzz::text(data, size));
    (void)obj_material_use(fuzz::text(data, size));
    (void)ply_texture_file(fuzz::text(data, size));
    (void)image_mime_type(fuzz::text(data, size));
  });
}
