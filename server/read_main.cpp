// cgview-read: reads ONE upload for the server, so that whatever a hostile
// file does to a parser (a decoder allocating for a count no byte backs, a
// crash) happens in this process, under the server's memory and time limits
// for it, and not in the server.
//
//   cgview-read --read-upload DIR   DIR/request.json and DIR/upload in,
//                                   DIR/result.json (or DIR/error.json) out
//
// A program of its own rather than a mode of cgview-worker: it links the
// readers alone, and starts in about 6 ms where the worker, with every
// algorithm and its libraries, takes about 45 (docs/BENCHMARKS.md).
#include <cstdio>
#include <string>

#include "upload_read.h"

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--read-upload") return cgview::server::read_upload_main(argv[2]);
  std::fputs("usage: cgview-read --read-upload DIR (the server runs it for each upload)\n", stderr);
  return 64;
}
