// The skeleton readers: the first byte picks the format (polylines, cg, obj,
// json), the rest is the file.
#include "fuzz.h"
#include "io/skeleton_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  if (size == 0) return 0;
  const SkeletonFormat formats[] = {SkeletonFormat::polylines, SkeletonFormat::cg, SkeletonFormat::obj,
                                    SkeletonFormat::json};
  return fuzz::expect_answer(
      [&] { (void)read_skeleton_bytes(fuzz::text(data + 1, size - 1), formats[data[0] % 4], "fuzz.skeleton"); });
}
