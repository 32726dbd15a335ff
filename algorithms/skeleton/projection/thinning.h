// What thin's stages share (skeleton/projection/thin.h): the domain of
// voxels it walks, numbered, the shortest-path trees over it and the
// skeleton they grow.  Private to skeleton/projection.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string_view>
#include <vector>

#include "core/skeleton.h"
#include "core/union_find.h"
#include "core/voxel_grid.h"
#include "skeleton/projection/lattice.h"

namespace cgview {
class Context;
}  // namespace cgview

namespace cgview::skeleton {

struct Thinning {
  // The domain, numbered (the arrays below are over it): see the constructor.
  Thinning(const VoxelGrid& votes, const std::vector<float>& radius, double threshold, double min_branch);

  // The tree: intensity-driven shortest paths from each component's most
  // voted voxel, and TEASAR's branches from them.  `tunnels`: the paths go
  // on over the whole component, so that the trees meet around tunnels.
  void grow_tree(bool tunnels, double branch_votes);
  // The loops of a closed mesh, at most `max_loops`: its tunnels
  // (thin_tunnels.cpp).  The tree's ends beside a closing are marked in `closed`.
  void close_tunnels(int max_loops, const std::function<bool(const Vec3&)>& inside);
  // The loops of another mesh: gaps between an end and a far part of the
  // skeleton, through voted voxels (thin_gaps.cpp).
  void close_gaps();
  // Terminal branches shorter than min_branch, or ending where a loop was
  // closed, go (a closing path may run into a branch short of its end).
  void prune_after_loops();

  // The domain's 26-neighbours of a numbered voxel: f(number, step k); from
  // step `ahead` on, only those ahead in the scan order (numbered after it:
  // each pair once; steps26 goes k from -1 to 1).  Looked up in the grid's
  // numbering each time: the walks visit about half the domain once, so a
  // table of all of them would cost more than it saves.
  template <class F>
  void neighbours(std::size_t c, F&& f, std::size_t first = 0) const {
    const std::int32_t* here = &id[vox[c]];
    for (std::size_t k = first; k < 26; ++k)
      if (const std::int32_t m = here[offset[k]]; m >= 0) f(std::size_t(m), k);
  }
  static constexpr std::size_t ahead = 13;
  // The skeleton node of a numbered voxel, made on first use.
  Index node(std::size_t c);
  // Whether a target is within the balls of the branches so far.
  bool covered(std::size_t c) const;
  // How far a branch through a voxel covers, in voxels.
  double cover(std::size_t c) const { return 1.5 * thick[c] + 2; }
  // Distances along the skeleton from `from` into g (Dijkstra over its
  // edges, in voxels), with the way back in `back`.
  void along_skeleton(Index from);
  // The tree's state once grown, which the loops start from.
  void tree_done();
  // Progress: `fraction` of thin, mapped onto [progress_from, progress_to]
  // of the run and passed to ctx (at most every 1% of thin, or when the
  // stage changes), which is also asked for cancellation (throws
  // Cancelled).  Nothing without a ctx.
  void progress(double fraction, std::string_view stage);

  const VoxelGrid& votes;
  const Lattice L;
  const std::vector<float>& I;  // the votes
  float top = 0;                // the most votes
  Skeleton s;
  double least_target = 0;       // a target's least votes
  std::vector<std::int32_t> id;  // a voxel's number in the domain (grids up to 512³ fit 32 bits)
  std::vector<std::size_t> vox;  // a number's voxel
  std::vector<std::ptrdiff_t> offset;
  const std::vector<Step>& step;
  UnionFind sets;  // the components (each joined to its lowest number)
  std::size_t count = 0;
  std::vector<std::uint8_t> target;
  std::vector<double> r2;                       // the intensity weight of a step onto a voxel
  std::vector<float> thick;                     // the local radius of the shape, in voxels
  std::vector<std::uint32_t> targets_of;        // of a component, at its lowest number
  double vs = 0, diagonal = 0, min_branch = 0;  // min_branch in voxels
  std::vector<std::int32_t> node_of;            // skeleton node of a numbered voxel
  std::vector<std::uint8_t> done;               // voxels of components already processed
  std::vector<double> cost, along;
  std::vector<std::int32_t> parent;
  // The voxels a branch covers: those within 1.5 x the local radius + 2
  // (in voxels, rounded up) of its voxels, kept as the balls (centre,
  // squared radius); only targets are ever asked about.
  std::vector<std::array<int, 4>> balls;
  std::vector<std::uint8_t> reached;  // targets that started a branch

  // Set by tree_done for the loops.
  std::vector<std::size_t> voxel_of;  // a node's numbered voxel
  std::vector<std::uint32_t> degree;  // the tree's
  std::size_t tree_edges = 0;
  std::vector<std::uint8_t> closed;  // the tree's ends beside a loop's closing
  std::vector<double> g;             // along_skeleton's distances
  std::vector<std::int32_t> back;    // and its way back
  Adjacency adj;
  std::size_t adj_edges = 0;  // the edges adj was made from

  const Context* ctx = nullptr;
  double progress_from = 0, progress_to = 1;
  double reported = -1;               // the last fraction passed on
  std::string_view reported_stage{};  // and its stage (a literal)
};

}  // namespace cgview::skeleton
