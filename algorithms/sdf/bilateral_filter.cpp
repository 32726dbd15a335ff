#include "sdf/bilateral_filter.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "sdf/bilateral_sampled.h"
#include "sdf/bilateral_sums.h"
#include "sdf/parallel_blocks.h"

namespace cgview::sdf {
namespace {

constexpr std::size_t kBlock = 64;  // faces per walk: a bit each in a word
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint32_t kFree = kNone - 1;  // queued by an earlier block's walk, not walked

// Blocks of up to 64 faces to smooth, each grown breadth-first from a seed so
// that its faces lie close together and their windows overlap.  The walk that
// gathers a block goes through the other faces, and gives up after `reach`
// faces (the last scattered faces of a sparse list make blocks of their own).
// With `claim` (a sparse list: the accelerated SDF's samples), a block's walk
// goes only through faces no earlier block's walk went through, so that each
// face is walked once: walking through the earlier blocks' faces to the next
// free ones cost more than the smoothing itself (1.5 ms of polygon_mesh's 2.7
// with 2,400 samples in 32k faces).
std::vector<std::vector<std::uint32_t>> blocks_of(const Adjacency& g, const std::vector<char>& wanted,
                                                  std::size_t reach, bool claim = false) {
  const std::size_t n = g.size();
  std::vector<char> taken(n, 0);
  std::vector<std::uint32_t> seen(n, kNone), queue;
  std::vector<std::vector<std::uint32_t>> blocks;
  for (std::size_t s = 0; s < n; ++s) {
    if (!wanted[s] || taken[s]) continue;
    std::vector<std::uint32_t> block;
    queue.assign(1, std::uint32_t(s));
    seen[s] = std::uint32_t(blocks.size());
    std::size_t k = 0;
    for (; k < queue.size() && block.size() < kBlock && k < reach; ++k) {
      const std::uint32_t f = queue[k];
      if (wanted[f] && !taken[f]) taken[f] = 1, block.push_back(f);
      for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h)
        if (claim ? seen[*h] == kNone || seen[*h] == kFree : seen[*h] != blocks.size())
          seen[*h] = std::uint32_t(blocks.size()), queue.push_back(*h);
    }
    // Faces queued but not walked stay free for the next blocks.
    if (claim)
      for (std::size_t j = k; j < queue.size(); ++j) seen[queue[j]] = kFree;
    blocks.push_back(std::move(block));
  }
  return blocks;
}

// One walk for a block: the faces met, with the bits of the block's faces
// whose windows they are in, and for each face of the block the values of
// its window with their rings' half of the weights' exponent.  Arrays keep
// their size from block to block (a walk allocates nothing once they are
// large enough), and are sized before the inner loops, which then write
// through plain pointers.
class Walk {
 public:
  std::span<const float> values(std::size_t i) const { return {value_[i].data(), count_[i]}; }
  std::span<const float> exponents(std::size_t i) const { return {exponent_[i].data(), count_[i]}; }

  void run(const Adjacency& g, const std::vector<double>& v, std::span<const std::uint32_t> block,
           const std::vector<float>& ring_exponent) {
    const int window = int(ring_exponent.size()) - 1;
    gather(g, v, block, window);
    front_.clear();
    for (std::size_t i = 0; i < block.size(); ++i) {
      count_[i] = 0;
      reached_[i] |= std::uint64_t(1) << i;  // the block's faces come first
      front_.push_back({std::uint32_t(i), std::uint64_t(1) << i});
    }
    std::uint64_t* reached = reached_.data();
    std::uint64_t* incoming = incoming_.data();
    std::uint32_t* touched = touched_.data();
    const std::uint32_t* near = near_.data();
    const std::uint32_t* near_at = near_at_.data();
    for (int level = 0;; ++level) {
      record(block.size(), ring_exponent[std::size_t(level)]);
      if (level == window) return;
      std::size_t touches = 0;
      for (const auto& [l, bits] : front_)
        for (std::uint32_t k = near_at[l]; k < near_at[l + 1]; ++k) {
          const std::uint32_t m = near[k];
          if (!incoming[m]) touched[touches++] = m;
          incoming[m] |= bits;
        }
      next_.clear();
      for (std::size_t t = 0; t < touches; ++t) {
        const std::uint32_t m = touched[t];
        const std::uint64_t fresh = incoming[m] & ~reached[m];
        incoming[m] = 0;
        if (fresh) reached[m] |= fresh, next_.push_back({m, fresh});
      }
      front_.swap(next_);
    }
  }

 private:
  std::vector<std::uint32_t> stamp_, slot_;  // per face of the mesh: the walk's own numbering
  std::uint32_t epoch_ = 0;
  // Per face within the window of a face of the block:
  std::vector<std::uint32_t> face_;                                    // its number in the mesh
  std::vector<std::uint16_t> ring_;                                    // its ring from the block's nearest face
  std::vector<std::uint32_t> near_at_, near_;                          // its neighbours among them
  std::vector<float> face_value_;                                      // its value (the sums are in float: see below)
  std::vector<std::uint64_t> reached_, incoming_;                      // whose windows it is in; reached at this ring
  std::vector<std::pair<std::uint32_t, std::uint64_t>> front_, next_;  // faces first met at a ring, and by whom
  std::vector<std::uint32_t> touched_;
  std::vector<float> value_[kBlock], exponent_[kBlock];
  std::size_t count_[kBlock] = {};

  // The faces within `window` rings of the block's, numbered from 0 (the
  // block's first), with their values and their neighbours among them in
  // those numbers: the walks of every ring then stay in these arrays.
  void gather(const Adjacency& g, const std::vector<double>& v, std::span<const std::uint32_t> block, int window) {
    if (stamp_.size() != g.size()) stamp_.assign(g.size(), 0), slot_.resize(g.size()), epoch_ = 0;
    if (++epoch_ == 0) std::fill(stamp_.begin(), stamp_.end(), 0), epoch_ = 1;
    face_.clear(), ring_.clear();
    const auto add = [&](std::uint32_t f, std::uint16_t ring) {
      stamp_[f] = epoch_;
      slot_[f] = std::uint32_t(face_.size());
      face_.push_back(f);
      ring_.push_back(ring);
    };
    for (std::uint32_t f : block) add(f, 0);
    for (std::size_t k = 0; k < face_.size(); ++k) {
      if (ring_[k] == window) continue;
      for (const std::uint32_t* h = g.begin(face_[k]); h != g.end(face_[k]); ++h)
        if (stamp_[*h] != epoch_) add(*h, std::uint16_t(ring_[k] + 1));
    }
    const std::size_t met = face_.size();
    face_value_.resize(met), reached_.assign(met, 0), incoming_.assign(met, 0);
    near_at_.resize(met + 1);
    near_.clear();
    for (std::size_t k = 0; k < met; ++k) {
      face_value_[k] = float(v[face_[k]]);
      near_at_[k] = std::uint32_t(near_.size());
      // A face on the outermost ring may have neighbours beyond: no walk
      // of the block reaches them within the window.
      for (const std::uint32_t* h = g.begin(face_[k]); h != g.end(face_[k]); ++h)
        if (stamp_[*h] == epoch_) near_.push_back(slot_[*h]);
    }
    near_at_[met] = std::uint32_t(near_.size());
    touched_.resize(std::max(touched_.size(), near_.size()));
  }

  // A face joins the windows whose bits first reach it at this ring; faces
  // without a value are walked through but not averaged.
  void record(std::size_t sources, float exponent) {
    float* value[kBlock];
    float* expo[kBlock];
    for (std::size_t i = 0; i < sources; ++i) {
      if (value_[i].size() < count_[i] + front_.size()) {
        const std::size_t size = std::max(count_[i] + front_.size(), 2 * value_[i].size());
        value_[i].resize(size), exponent_[i].resize(size);
      }
      value[i] = value_[i].data();
      expo[i] = exponent_[i].data();
    }
    const float* face_value = face_value_.data();
    for (const auto& [l, bits] : front_) {
      const float x = face_value[l];
      if (std::isnan(x)) continue;
      for (std::uint64_t b = bits; b; b &= b - 1) {
        const int i = std::countr_zero(b);
        value[i][count_[i]] = x;
        expo[i][count_[i]++] = exponent;
      }
    }
  }
};

}  // namespace

int default_window(std::size_t faces) { return int(std::sqrt(double(faces) / 2000.0)) + 1; }

void bilateral_smooth(const Adjacency& graph, std::vector<double>& values, int window, const Context* ctx,
                      std::span<const std::uint32_t> only, double range) {
  const std::size_t n = values.size();
  if (window <= 0) window = default_window(n);
  std::vector<char> wanted(n, only.empty() ? 1 : 0);
  for (std::uint32_t f : only) wanted[f] = 1;
  for (std::size_t f = 0; f < n; ++f)
    if (std::isnan(values[f])) wanted[f] = 0;
  const auto blocks = blocks_of(graph, wanted, 64 * kBlock, !only.empty());
  // exp(-ring^2 / (2 spatial^2)) exp(-dv^2 / (2 range^2)) as one exp: the
  // rings' half of the exponent by ring.
  const double spatial = window / 2.0;
  std::vector<float> ring_exponent(std::size_t(window) + 1);
  for (int l = 0; l <= window; ++l) ring_exponent[std::size_t(l)] = float(0.5 * (l / spatial) * (l / spatial));

  std::vector<double> out = values;
  parallel_blocks(blocks.size(), 4, thread_count(), ctx, 0.0, 1.0, "smoothing", [&](std::size_t b, std::size_t e) {
    thread_local Walk walk;
    for (std::size_t k = b; k < e; ++k) {
      const std::vector<std::uint32_t>& block = blocks[k];
      walk.run(graph, values, block, ring_exponent);
      for (std::size_t i = 0; i < block.size(); ++i) {
        // In float, eight to a vector instruction: the weights' rounding
        // moves a result by about 1e-7 of its window's spread.
        const std::span<const float> x = walk.values(i);
        const float c = float(values[block[i]]);
        const double dev = std::sqrt(double(squared_deviation(x.data(), x.size(), c)) / double(x.size()));
        if (dev == 0) continue;  // out keeps c
        float sum = 0, weights = 0;
        weighted_sums(x.data(), walk.exponents(i).data(), x.size(), c, float(0.5 / (range * range * dev * dev)), sum,
                      weights);
        out[block[i]] = double(sum) / double(weights);
      }
    }
  });
  values = std::move(out);
}

void bilateral_smooth(const Mesh& mesh, const Adjacency& graph, std::vector<double>& values, int window,
                      const Context* ctx) {
  const int own = default_window(values.size());
  if (window <= 0) window = own;
  if (window >= kSampledWindow && own >= kSampledWindow) bilateral_smooth_sampled(mesh, graph, values, window, ctx);
  else bilateral_smooth(graph, values, window, ctx);
}

}  // namespace cgview::sdf
