// A zip upload as the upload reader takes it (upload_read.h): unzipped, its
// one mesh file found and read, its MTL and images matched, the report made.
#include <cstddef>

#include "fuzz.h"
#include "upload_read.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  return fuzz::expect_answer(
      [&] { (void)server::read_upload("fuzz.zip", "", fuzz::text(data, size), std::size_t(64) << 20); });
}
