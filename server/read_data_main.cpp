// cgview-read-data: reads ONE data upload for the server (a voxel grid, a
// skeleton or a scalar field: server/data_read.h), in a process of its own
// under the limits mesh uploads are read under, for the same reason.
//
//   cgview-read-data --read-data DIR   DIR/request.json and DIR/upload in,
//                                      DIR/out/ and DIR/result.json (or DIR/error.json) out
//
// Apart from cgview-read because it links the voxel formats (OpenVDB and
// its libraries), which cost every start about 40 ms that mesh uploads
// need not pay (docs/BENCHMARKS.md).
#include <cstdio>
#include <string>

#include "data_read.h"

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--read-data") return cgview::server::read_data_main(argv[2]);
  std::fputs("usage: cgview-read-data --read-data DIR (the server runs it for each data upload)\n", stderr);
  return 64;
}
