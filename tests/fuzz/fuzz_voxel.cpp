// The voxel-grid readers a job's grid or an upload goes through: the first
// byte picks the format (binvox, nrrd, vti, vox), the rest is the file.
#include <string>

#include "fuzz.h"
#include "voxel/voxel_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  if (size == 0) return 0;
  const std::string bytes(fuzz::text(data + 1, size - 1));
  return fuzz::expect_answer([&] {
    switch (data[0] % 4) {
      case 0:
        (void)decode_binvox(bytes);
        break;
      case 1:
        (void)decode_nrrd(bytes);
        break;
      case 2:
        (void)decode_vti(bytes);
        break;
      default:
        (void)decode_vox(bytes);
        break;
    }
  });
}
