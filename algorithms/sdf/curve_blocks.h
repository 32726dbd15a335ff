// A face graph cut into blocks of consecutive faces along a Morton curve
// through their centroids (sdf/curve_order.h), each with the arcs between
// its own faces: work that walks the graph one face after another (the
// accelerated SDF's choice of samples) then runs a block on each core.  The
// cut depends on the mesh alone, never on the machine's cores, so that a
// result is the same on any machine.
#pragma once

#include <cstdint>
#include <vector>

#include "core/mesh.h"
#include "sdf/parallel_blocks.h"

namespace cgview::sdf {

struct CurveBlocks {
  std::vector<std::vector<std::uint32_t>> faces;  // each block's faces, ascending
  std::vector<Adjacency> graphs;                  // each block's arcs, both ends its own, in its local numbers
  std::vector<std::vector<std::uint32_t>> arcs;   // each of those arcs' place in the whole graph's items
  std::size_t size() const { return faces.size(); }
};

// floor(faces / size) blocks of as near equal sizes as can be (each at
// least `size` faces), the k-th of the faces whose places i along the curve
// have floor(i * blocks / faces) == k.  Under 2 * size faces the whole
// graph is the one block, and nothing is listed: `faces`, `graphs` and
// `arcs` are empty.
CurveBlocks curve_blocks(const Mesh& mesh, const Adjacency& face_graph, std::size_t size);

// f(k) for each block k of `blocks`, on every core, a block at a time (the
// blocks' work differs).
template <class F>
void each_block(const CurveBlocks& blocks, const F& f) {
  parallel_blocks(blocks.size(), 1, threads_for(blocks.size(), 1), nullptr, 0, 0, "",
                  [&](std::size_t b, std::size_t e) {
                    for (std::size_t k = b; k < e; ++k) f(k);
                  });
}

}  // namespace cgview::sdf
