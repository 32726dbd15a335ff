// Animation: a mesh and more position arrays for its vertices (frames), as
// chaos_animate returns (positions after 1..K steps of a map), and the
// compact binary form it is saved and served in.
//
// The .frames format (little-endian; docs in protocol/API.md):
//   offset  0  char[4]   "CGVF"
//           4  uint32    version (1)
//           8  uint32    n, vertex count
//          12  uint32    f, face count
//          16  uint32    m, frame count (frame 0 is the base mesh's positions)
//          20  float32[3] lo, float32[3] hi: the box of every frame's positions
//          44  uint32[3 f] the faces
//              uint16[3 n] per frame, m times: q = round((p - lo) / (hi - lo) * 65535)
//              (0 on an axis where hi == lo)
// so a frame costs 6 bytes a vertex, and a position comes back within
// (hi - lo) / 131070 on each axis.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"

namespace cgview {

struct Animation {
  Mesh base;                               // faces, and the positions of frame 0
  std::vector<std::vector<Vec3f>> frames;  // frames 1..K, one position per base vertex each
  std::size_t frame_count() const { return 1 + frames.size(); }
};

std::string encode_frames(const Animation& a);
// Throws InvalidInput naming the problem (bad magic, truncated, index out of
// range).  Positions come back quantized.
Animation decode_frames(std::string_view bytes);

}  // namespace cgview
