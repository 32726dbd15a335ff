#include "sdf/curve_blocks.h"

#include "sdf/curve_order.h"

namespace cgview::sdf {

CurveBlocks curve_blocks(const Mesh& mesh, const Adjacency& g, std::size_t size) {
  const std::size_t n = g.size(), count = size > 0 ? n / size : 0;
  CurveBlocks out;
  if (count < 2) return out;
  const std::vector<std::uint32_t> order = face_curve_order(mesh);
  std::vector<std::uint32_t> block(n), local(n);
  for (std::size_t i = 0; i < n; ++i) block[order[i]] = std::uint32_t(i * count / n);
  out.faces.resize(count);
  for (std::size_t f = 0; f < n; ++f) {
    std::vector<std::uint32_t>& faces = out.faces[block[f]];
    local[f] = std::uint32_t(faces.size());
    faces.push_back(std::uint32_t(f));
  }
  out.graphs.resize(count);
  out.arcs.resize(count);
  each_block(out, [&](std::size_t k) {
    Adjacency& a = out.graphs[k];
    a.offsets.reserve(out.faces[k].size() + 1);
    a.offsets.push_back(0);
    for (std::uint32_t f : out.faces[k]) {
      for (std::uint32_t j = g.offsets[f]; j < g.offsets[f + 1]; ++j)
        if (block[g.items[j]] == k) a.items.push_back(local[g.items[j]]), out.arcs[k].push_back(j);
      a.offsets.push_back(std::uint32_t(a.items.size()));
    }
  });
  return out;
}

}  // namespace cgview::sdf
