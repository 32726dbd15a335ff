#include "sdf/sdf_poisson.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <barrier>
#include <cmath>
#include <latch>
#include <limits>
#include <numeric>
#include <optional>

#include "core/threads.h"
#include "sdf/curve_blocks.h"
#include "filters/vertex_curvatures.h"

namespace cgview::sdf {
namespace {

// Each face's nearest known face's value (breadth-first from all of them):
// where the diffusion and the conjugate gradients start.
std::vector<double> nearest_known(const Adjacency& g, const std::vector<double>& values) {
  std::vector<double> out = values;
  std::vector<std::uint32_t> queue;
  for (std::size_t f = 0; f < values.size(); ++f)
    if (!std::isnan(values[f])) queue.push_back(std::uint32_t(f));
  for (std::size_t k = 0; k < queue.size(); ++k)
    for (const std::uint32_t* h = g.begin(queue[k]); h != g.end(queue[k]); ++h)
      if (std::isnan(out[*h])) out[*h] = out[queue[k]], queue.push_back(*h);
  return out;
}

// Each arc's weight in the diffusion, in face_graph.items' order: ((1 + cos
// a) / 2)^k, a the angle between the two faces' normals, k = 8 across a
// concave edge and 4 across a convex one.  The SDF jumps where parts meet,
// at concave creases (where the SDF's segmentation cuts), and the
// unweighted sweeps carried a thin part's value into the thick one there:
// mannequin-devil 3.71% to 3.40% of the range off the full SDF, fandisk_large
// 2.40% to 2.22% (docs/BENCHMARKS.md; the exponents the best of 0-32).
// And each arc's cost for nearest_known: 1 + round(12 (1 - weight)), 1 to
// 13 (a concave crease the dearest).  Of the scales 2 to 30, the larger came
// closer to the full SDF on all ten meshes of 20k faces or more (12:
// mannequin-devil 3.33% to 3.32%, polygon_mesh 3.91% to 3.80%, bear_bis
// 1.28% to 1.25%; 30: 3.29%, 3.78%, 1.21%), but from 20 on polygon_mesh's
// faces beside its escaped regions came out low on average (a mean signed
// error of -0.54% of the range at 30, against -0.48% at 12).
constexpr double kCostScale = 12;
struct ArcWeights {
  std::vector<float> weight;
  std::vector<std::uint8_t> cost;
};

ArcWeights arc_weights(const Mesh& mesh, const Adjacency& g) {
  // Per face its unit normal and its centroid's height along it; per arc
  // the cosine and whether the neighbour's centroid lies above the plane.
  struct Plane {
    Vec3 normal, centre;
    double height;
  };
  // Both passes on every core: 70 ms on one for the 1.42M-face mesh.  The
  // normals as face_normals makes them, in the planes' pass.
  const std::size_t n = g.size();
  std::vector<Plane> plane(n);
  const int threads = threads_for(n, kItemsPerThread);
  on_shares(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      plane[f].normal = normalized(face_cross(mesh, f));
      plane[f].centre = face_centroid(mesh, f);
      plane[f].height = dot(plane[f].normal, plane[f].centre);
    }
  });
  ArcWeights w{std::vector<float>(g.items.size()), std::vector<std::uint8_t>(g.items.size())};
  on_shares(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t f = b; f < e; ++f) {
      const Plane& pf = plane[f];
      for (std::uint32_t k = g.offsets[f]; k < g.offsets[f + 1]; ++k) {
        const Plane& ph = plane[g.items[k]];
        const double x = (1 + std::clamp(dot(pf.normal, ph.normal), -1.0, 1.0)) / 2, x4 = (x * x) * (x * x);
        const double weight = dot(pf.normal, ph.centre) > pf.height ? x4 * x4 : x4;  // concave: above f's plane
        w.weight[k] = float(weight);
        w.cost[k] = std::uint8_t(1 + int(kCostScale * (1 - weight) + 0.5));
      }
    }
  });
  return w;
}

// Each face's nearest known face's value as nearest_known, by the arcs'
// costs (Dial's buckets, one per distance modulo the largest cost + 1):
// where the weighted diffusion starts.  Plain rings started the faces
// beyond a crease from the sample across it, which the few sweeps do not
// undo (3.53% to 3.40% on mannequin-devil).
std::vector<double> nearest_known(const Adjacency& g, const ArcWeights& a, const std::vector<double>& values) {
  const std::size_t n = g.size();
  std::vector<double> out = values;
  std::vector<std::uint32_t> dist(n, std::numeric_limits<std::uint32_t>::max());
  constexpr std::size_t kBuckets = std::size_t(kCostScale) + 2;  // more than the largest cost
  std::vector<std::uint32_t> bucket[kBuckets];
  std::size_t queued = 0;
  for (std::size_t f = 0; f < n; ++f)
    if (!std::isnan(values[f])) dist[f] = 0, bucket[0].push_back(std::uint32_t(f)), ++queued;
  for (std::uint32_t d = 0; queued > 0; ++d) {
    std::vector<std::uint32_t>& now = bucket[d % kBuckets];
    for (std::size_t i = 0; i < now.size(); ++i) {
      const std::uint32_t f = now[i];
      if (dist[f] != d) continue;  // reached more cheaply since it was queued
      for (std::uint32_t k = g.offsets[f]; k < g.offsets[f + 1]; ++k) {
        const std::uint32_t h = g.items[k], next = d + a.cost[k];
        if (next >= dist[h]) continue;
        dist[h] = next, out[h] = out[f];
        bucket[next % kBuckets].push_back(h), ++queued;
      }
    }
    queued -= now.size();
    now.clear();
  }
  return out;
}

// all[at[i]] for each i, and back.
template <class T>
std::vector<T> gather(const std::vector<T>& all, const std::vector<std::uint32_t>& at) {
  std::vector<T> out(at.size());
  for (std::size_t i = 0; i < at.size(); ++i) out[i] = all[at[i]];
  return out;
}
template <class T>
void scatter(const std::vector<T>& part, const std::vector<std::uint32_t>& at, std::vector<T>& all) {
  for (std::size_t i = 0; i < at.size(); ++i) all[at[i]] = part[i];
}

// nearest_known within each block where the mesh is cut (sdf/curve_blocks.h),
// on every core: a face beside a border may take its own block's sample
// where the other block's is nearer.  A face of a block whose part of the
// mesh there has no known face is reached across the border afterwards.
// With `a`, by the arcs' costs.
std::vector<double> nearest_known(const Adjacency& g, const CurveBlocks& blocks, const ArcWeights* a,
                                  const std::vector<double>& values) {
  const auto whole = [&](const std::vector<double>& v) { return a ? nearest_known(g, *a, v) : nearest_known(g, v); };
  if (blocks.size() == 0) return whole(values);
  std::vector<double> out(values.size());
  each_block(blocks, [&](std::size_t k) {
    const std::vector<double> own = gather(values, blocks.faces[k]);
    if (!a) return scatter(nearest_known(blocks.graphs[k], own), blocks.faces[k], out);
    const ArcWeights costs{{}, gather(a->cost, blocks.arcs[k])};
    scatter(nearest_known(blocks.graphs[k], costs, own), blocks.faces[k], out);
  });
  if (std::any_of(out.begin(), out.end(), [](double v) { return std::isnan(v); })) out = whole(out);
  return out;
}

// kappa(p) * lambda: the mean of the face's vertices' mean curvature, times
// curvature_weight * l^2.
std::vector<double> guidance(const Mesh& mesh, const Adjacency& g, double weight) {
  std::vector<double> out(mesh.faces.size(), 0.0);
  if (weight == 0) return out;
  const VertexCurvatures k = vertex_curvatures(mesh);
  double length = 0;
  std::size_t arcs = 0;
  for (std::size_t f = 0; f < g.size(); ++f)
    for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h, ++arcs)
      length += norm(face_centroid(mesh, f) - face_centroid(mesh, *h));
  const double l = arcs ? length / double(arcs) : 0.0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    out[f] = weight * l * l * (k.mean[t[0]] + k.mean[t[1]] + k.mean[t[2]]) / 3.0;
  }
  return out;
}

// Samples are about 1 / sqrt(fraction) rings apart, and t sweeps spread a
// value over about sqrt(t) rings: 0.6 / fraction sweeps reach between
// samples without averaging over the next ones (the constant measured on
// four meshes at 5-20%, docs/DESIGN.md).  The cap bounds the time at
// fractions below 0.25%.
int sweeps_for(const SdfFastParams& p) { return int(std::clamp(std::lround(0.6 / p.fraction), 1L, 256L)); }

// `sweeps` Jacobi sweeps of the equation over the `unknown` faces of x:
// each takes its neighbours' mean, less its guidance term (none if empty);
// with arc weights `w` (arc_weights's; none if empty), their weighted mean.
// The unknown faces split over the cores, one share each (a sweep reads
// only the last one's values), the shares meeting after each sweep: a
// thread for each 8k faces at most, as one costs about as much to start
// (35 us on the 2-core build machine) as a sweep over 16k faces, and the
// sweeps are several (6 at 10%); `cores` threads at most.
void jacobi(const Adjacency& g, const std::vector<std::uint32_t>& unknown, const std::vector<double>& guide, int sweeps,
            std::vector<double>& x, const std::vector<float>& w = {}, int cores = thread_count()) {
  std::vector<double> next = x;
  std::vector<double>* from = &x;
  std::vector<double>* to = &next;
  const auto sweep = [&](std::size_t begin, std::size_t end) {
    const std::vector<double>& in = *from;
    std::vector<double>& out = *to;
    for (std::size_t i = begin; i < end; ++i) {
      const std::uint32_t f = unknown[i];
      double sum = guide.empty() ? 0.0 : -guide[f];
      if (w.empty()) {
        for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) sum += in[*h];
        out[f] = sum / double(g.degree(f));
      } else {
        double weights = 0;
        for (std::uint32_t k = g.offsets[f]; k < g.offsets[f + 1]; ++k)
          sum += double(w[k]) * in[g.items[k]], weights += double(w[k]);
        out[f] = weights > 0 ? sum / weights : in[f];
      }
    }
  };
  const int threads = threads_for(unknown.size(), 8192, cores);
  std::barrier swept(threads, [&]() noexcept { std::swap(from, to); });
  on_shares(unknown.size(), threads, [&](std::size_t begin, std::size_t end) {
    for (int s = 0; s < sweeps; ++s) {
      sweep(begin, end);
      swept.arrive_and_wait();
    }
  });
  if (from != &x) x.swap(next);
}

// The unknown faces' values (`row` numbers them, -1 for the others) from the
// kept samples' in out.values, by p.solver, started from `start` (each
// face's nearest kept sample's value).
void solve(const Mesh& mesh, const Adjacency& g, const SdfFastParams& p, const std::vector<double>& start,
           const std::vector<std::uint32_t>& unknown, const std::vector<std::int64_t>& row, const ArcWeights& weights,
           int cores, FastSdf& out) {
  if (unknown.empty()) return;
  const std::vector<double> rhs_guide = guidance(mesh, g, p.curvature_weight);

  if (p.solver == Solver::diffusion) {
    out.values = start;
    out.iterations = sweeps_for(p);
    jacobi(g, unknown, rhs_guide, out.iterations, out.values, weights.weight, cores);
    return;
  }

  std::vector<Eigen::Triplet<double>> t;
  t.reserve(g.items.size() + unknown.size());
  Eigen::VectorXd b(Eigen::Index(unknown.size()));
  for (std::size_t r = 0; r < unknown.size(); ++r) {
    const std::uint32_t f = unknown[r];
    double known = 0;
    for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) {
      if (row[*h] >= 0) t.emplace_back(Eigen::Index(r), Eigen::Index(row[*h]), -1.0);
      else known += out.values[*h];  // a Dirichlet value
    }
    t.emplace_back(Eigen::Index(r), Eigen::Index(r), double(g.degree(f)));
    b[Eigen::Index(r)] = known - rhs_guide[f];
  }
  Eigen::SparseMatrix<double> A(Eigen::Index(unknown.size()), Eigen::Index(unknown.size()));
  A.setFromTriplets(t.begin(), t.end());
  Eigen::VectorXd x;
  if (p.solver == Solver::cholesky) {
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
    if (ldlt.info() != Eigen::Success) throw Error("the Poisson system could not be factorized");
    x = ldlt.solve(b);
  } else {
    Eigen::VectorXd x0(Eigen::Index(unknown.size()));
    for (std::size_t r = 0; r < unknown.size(); ++r) x0[Eigen::Index(r)] = start[unknown[r]];
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg(A);
    cg.setTolerance(1e-6);  // relative residual: far below the SDF's own noise
    x = cg.solveWithGuess(b, x0);
    out.iterations = int(cg.iterations());
  }
  for (std::size_t r = 0; r < unknown.size(); ++r) out.values[unknown[r]] = x[Eigen::Index(r)];
}

// The faces whose nearest sample escaped are taken as the region without a
// value they mark, and given what the full SDF gives such a region
// (sdf/sdf_rays.h's postprocess): fill_missing (CGAL's: in the faces'
// order, each its neighbours' mean as they are then, else the smallest
// value), then the bilateral filter's smoothing over the faces within its
// window of the border.  The full SDF ramps from the smallest value up to
// its neighbours' over a few rings there; the smallest value alone,
// interpolated, missed that ramp by 8-10% of the range (docs/BENCHMARKS.md).
//
// The region depends on the samples alone: escaped_region finds it on the
// second core while the first solves for the other faces (fill_escaped).
struct EscapedRegion {
  std::vector<std::uint32_t> faces;  // whose nearest sample escaped
  std::vector<std::uint32_t> near;   // those within the filter's window of its border
};

EscapedRegion escaped_region(const Adjacency& g, const ArcWeights& weights, const SdfFastParams& p,
                             const std::vector<std::uint32_t>& samples, const std::vector<std::uint32_t>& escaped) {
  EscapedRegion region;
  if (escaped.empty()) return region;
  const std::size_t n = g.size();
  std::vector<double> mark(n, std::numeric_limits<double>::quiet_NaN());
  for (std::uint32_t s : samples) mark[s] = 0.0;
  for (std::uint32_t s : escaped) mark[s] = 1.0;
  // Nearest by the diffusion's arc costs: a hole's rim is often a crease
  // (mannequin-devil 3.40% to 3.33%, polygon_mesh 4.06% to 3.91%).
  mark = nearest_known(g, weights, mark);
  // The filter's ramp is swept over the faces within its window of the
  // region's border (its faces beside one outside it, whose neighbours'
  // mean fill_missing carries inwards in the faces' order): sweeps over
  // the whole region instead, or twice as many, came further from the full
  // SDF (polygon_mesh 3.15% to 3.17% and 3.29%).
  const int window = p.sdf.window > 0 ? p.sdf.window : default_window(n);
  std::vector<int> ring(n, std::numeric_limits<int>::max());
  std::vector<std::uint32_t>& near = region.near;
  for (std::size_t f = 0; f < n; ++f) {
    if (mark[f] != 1.0) continue;
    region.faces.push_back(std::uint32_t(f));
    for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h)
      if (mark[*h] != 1.0) {
        ring[f] = 0, near.push_back(std::uint32_t(f));
        break;
      }
  }
  for (std::size_t k = 0; k < near.size(); ++k)
    if (ring[near[k]] < window)
      for (const std::uint32_t* h = g.begin(near[k]); h != g.end(near[k]); ++h)
        if (ring[*h] > ring[near[k]] + 1) ring[*h] = ring[near[k]] + 1, near.push_back(*h);
  return region;
}

void fill_escaped(const Mesh& mesh, const Adjacency& g, const SdfFastParams& p, const EscapedRegion& region,
                  std::vector<double>& values) {
  if (region.faces.empty()) return;
  for (std::uint32_t f : region.faces) values[f] = std::numeric_limits<double>::quiet_NaN();
  fill_missing(mesh, g, values);
  // The filter's ramp by sweeps of neighbours' means over the same faces:
  // t sweeps spread a value over about sqrt(t) rings, and the filter's
  // Gaussian has a deviation of half its window, so window^2 / 6 sweeps
  // (the best of 2-8 on mannequin-devil and polygon_mesh, windows 4 and 5).
  // The filter itself came 0.1-0.2 points closer to the full SDF, for 13 ms
  // of polygon_mesh's 45 (a quarter of its faces have no ray that finds the
  // inside), which took it below 4x the full SDF's speed.
  const int window = p.sdf.window > 0 ? p.sdf.window : default_window(values.size());
  if (p.sdf.smooth) jacobi(g, region.near, {}, std::max(1, int(std::lround(window * window / 6.0))), values);
}

// The samples as a graph of their own: each face belongs to its nearest
// sample (breadth-first from all of them, the first to reach it), and two
// samples are neighbours where their regions touch.  `hop`: the mean rings
// between neighbours, each pair by the shortest way through its two
// regions' touching faces.
struct SampleGraph {
  Adjacency graph;  // over the samples' indices
  double hop = 1;
};

// Where the mesh is cut (sdf/curve_blocks.h), a face's nearest sample is
// sought within its block, each block on a core: samples of two blocks
// still touch across their border.
SampleGraph sample_graph(const Adjacency& g, const CurveBlocks& blocks, const std::vector<std::uint32_t>& samples) {
  const std::size_t n = g.size(), m = samples.size();
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> site(n, none), ring(n, 0);
  for (std::size_t k = 0; k < m; ++k) site[samples[k]] = std::uint32_t(k);
  // f(face) for every face, a block's faces on the block's core (writing
  // only what its own samples own), or all on this one.
  const auto each_face = [&](const auto& f) {
    if (blocks.size() == 0)
      for (std::size_t i = 0; i < n; ++i) f(std::uint32_t(i));
    else
      each_block(blocks, [&](std::size_t k) {
        for (std::uint32_t i : blocks.faces[k]) f(i);
      });
  };
  // Breadth-first from the samples, in their order, over a's faces (the
  // mesh's `face[i]`, or i itself).
  const auto walk = [&](const Adjacency& a, const std::uint32_t* face) {
    const auto id = [&](std::uint32_t i) { return face ? face[i] : i; };
    std::vector<std::uint32_t> queue;
    queue.reserve(a.size());
    for (std::uint32_t i = 0; i < a.size(); ++i)
      if (site[id(i)] != none) queue.push_back(i);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t f = id(queue[q]);
      for (const std::uint32_t* h = a.begin(queue[q]); h != a.end(queue[q]); ++h)
        if (const std::uint32_t to = id(*h); site[to] == none)
          site[to] = site[f], ring[to] = ring[f] + 1, queue.push_back(*h);
    }
  };
  if (blocks.size() == 0) walk(g, nullptr);
  else each_block(blocks, [&](std::size_t k) { walk(blocks.graphs[k], blocks.faces[k].data()); });
  // Each touching arc as (neighbour, rings) under its sample, counted first
  // and then placed; each sample's list then sorted, its repeats dropped
  // (the first of each neighbour is its shortest).
  const auto touches = [&](std::uint32_t f, const auto& take) {
    for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h)
      if (site[f] != site[*h] && site[f] != none && site[*h] != none) take(site[*h], ring[f] + 1 + ring[*h]);
  };
  std::vector<std::uint32_t> at(m + 1, 0);
  each_face([&](std::uint32_t f) { touches(f, [&](std::uint32_t, std::uint32_t) { ++at[site[f] + 1]; }); });
  for (std::size_t k = 0; k < m; ++k) at[k + 1] += at[k];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> touch(at[m]);
  {
    std::vector<std::uint32_t> next(at.begin(), at.end() - 1);
    each_face([&](std::uint32_t f) {
      touches(f, [&](std::uint32_t to, std::uint32_t rings) { touch[next[site[f]]++] = {to, rings}; });
    });
  }
  // Each sample's list sorted and its repeats dropped in place, counted,
  // then moved together.  A list is about six touches: a share of 8k
  // samples is about the work of a pass over 64k items.
  std::vector<std::uint32_t> kept(m + 1, 0);
  on_shares(m, threads_for(m, kItemsPerThread / 8), [&](std::size_t b, std::size_t e) {
    for (std::size_t k = b; k < e; ++k) {
      const auto first = touch.begin() + at[k], last = touch.begin() + at[k + 1];
      std::sort(first, last);
      kept[k + 1] = std::uint32_t(
          std::unique(first, last, [](const auto& x, const auto& y) { return x.first == y.first; }) - first);
    }
  });
  for (std::size_t k = 0; k < m; ++k) kept[k + 1] += kept[k];
  SampleGraph out;
  out.graph.offsets = kept;
  out.graph.items.resize(kept[m]);
  double rings = 0;
  for (std::size_t k = 0; k < m; ++k)
    for (std::uint32_t i = 0; i < kept[k + 1] - kept[k]; ++i)
      out.graph.items[kept[k] + i] = touch[at[k] + i].first, rings += touch[at[k] + i].second;
  if (!out.graph.items.empty()) out.hop = rings / double(out.graph.items.size());
  return out;
}

// The samples' values smoothed among themselves (those without a value
// walked through, as the full SDF's filter does): the full SDF's bilateral
// filter on their own graph, its window the full SDF's less a ring (the
// second round's samples lie closer together where the SDF varies, and a
// window of rings holds more of them there), in hops of the mean rings
// between neighbours.  The filter on the faces' rings visited every face of
// a window, ten for each sample in it: 0.81 s of sdf_fast's 3.1 s at 10% on
// the 1.42M-face mesh (window 26 rings), 0.20 s here (5 hops); and the
// samples' graph came closer to the full SDF on eight of the ten meshes of
// 20k faces or more, and on that one (docs/BENCHMARKS.md).  Its range
// Gaussian is narrower than the full filter's (1 RMS deviation of the
// window against CGAL's 1.5): a sample stands for the faces around it, so a
// neighbour's value that differs much is more likely another part than
// noise (mannequin-devil 3.20% to 3.04% off the full SDF, the mean over the
// ten meshes 1.49% to 1.46%, six meshes under 20k faces all closer, e.g.
// elephant 2.65% to 2.47%; 0.75 and 1.25 came no closer).  On the 1.42M-face
// mesh, where a window holds many more samples, 0.36% to 0.47%.
constexpr double kSampleRange = 1.0;
void smooth_samples(const Adjacency& g, const CurveBlocks& blocks, const SdfFastParams& p,
                    const std::vector<std::uint32_t>& samples, std::vector<double>& values) {
  const int window = std::max(1, (p.sdf.window > 0 ? p.sdf.window : default_window(g.size())) - 1);
  const SampleGraph sg = sample_graph(g, blocks, samples);
  std::vector<double> v(samples.size());
  for (std::size_t k = 0; k < samples.size(); ++k) v[k] = values[samples[k]];
  bilateral_smooth(sg.graph, v, std::max(1, int(std::lround(window / sg.hop))), nullptr, {}, kSampleRange);
  for (std::size_t k = 0; k < samples.size(); ++k) values[samples[k]] = v[k];
}

// Lowers `ring` (each face's rings from the samples so far) by a
// breadth-first walk from the faces in `queue`, new samples at ring 0, that
// stops where the rings are no lower.
void lower_rings(const Adjacency& g, std::vector<std::uint32_t>& ring, std::vector<std::uint32_t>& queue) {
  // The face and its ring read once: the stores into ring and queue would
  // else have them read again for every neighbour.
  for (std::size_t k = 0; k < queue.size(); ++k) {
    const std::uint32_t f = queue[k], next = ring[f] + 1;
    for (const std::uint32_t *h = g.begin(f), *end = g.end(f); h != end; ++h)
      if (ring[*h] > next) ring[*h] = next, queue.push_back(*h);
  }
}

// `count` more faces where the samples so far leave the SDF least certain:
// again and again the face that maximizes spread(f) * ring(f)^3, ring(f)
// its rings from the samples so far and spread(f) the local standard
// deviation of their values around it (uncertainty below).  The power of
// the rings weighs spreading them out against following the spread: of the
// exponents 1 to 4 measured on three meshes, 3 came closest to the full SDF
// (mannequin-devil 4.49%, 4.28%, 4.16%, 4.21%).  Faces whose score fell
// since they were queued (their ring did) go back in at their score now.
// `ring` comes from the first round's choice (spread_rings), which ends
// with every face's rings from its samples: walking them again cost a
// breadth-first pass over the mesh.
std::vector<std::uint32_t> more_samples(const Adjacency& g, std::vector<std::uint32_t> ring,
                                        const std::vector<double>& spread, std::size_t count) {
  const std::size_t n = g.size();
  constexpr std::uint32_t far = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> queue, added;
  queue.reserve(n);
  const auto score = [&](std::uint32_t f) {
    const double r = double(ring[f]);
    return spread[f] * r * r * r;
  };
  std::vector<std::pair<double, std::uint32_t>> heap;
  heap.reserve(n);
  for (std::size_t f = 0; f < n; ++f)
    if (ring[f] > 0 && ring[f] != far) heap.push_back({score(std::uint32_t(f)), std::uint32_t(f)});
  std::make_heap(heap.begin(), heap.end());
  while (added.size() < count && !heap.empty()) {
    std::pop_heap(heap.begin(), heap.end());
    const auto [was, f] = heap.back();
    heap.pop_back();
    if (ring[f] == 0) continue;
    const double now = score(f);
    if (now < was) {
      heap.push_back({now, f});
      std::push_heap(heap.begin(), heap.end());
      continue;
    }
    added.push_back(f);
    ring[f] = 0;
    queue.assign(1, f);
    lower_rings(g, ring, queue);
  }
  return added;
}

// The share of the samples cast in the first round, spread evenly: 60% of
// them, measured against 40-80% on ten meshes (docs/BENCHMARKS.md).
constexpr double kFirstRound = 0.6;

// How uncertain the first round leaves each face's SDF: the standard
// deviation of the samples' raw values around it (their local mean and mean
// square, each spread by the same few sweeps as the values; smoothing them
// first chose samples no better, for a third of this step's time), plus a
// thousandth of their range, so that where they agree the rings alone
// decide.  A sample whose rays escaped counts as the smallest value.
std::vector<double> uncertainty(const Adjacency& g, const CurveBlocks& blocks, const SdfFastParams& p,
                                const std::vector<std::uint32_t>& samples, const std::vector<double>& raw) {
  const std::size_t n = g.size();
  double smallest = HUGE_VAL, largest = -HUGE_VAL;
  for (double v : raw)
    if (!std::isnan(v)) smallest = std::min(smallest, v), largest = std::max(largest, v);
  if (smallest == HUGE_VAL) smallest = largest = 0;
  std::vector<double> mean(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < samples.size(); ++i) mean[samples[i]] = std::isnan(raw[i]) ? smallest : raw[i];
  std::vector<std::uint32_t> unknown;
  for (std::size_t f = 0; f < n; ++f)
    if (std::isnan(mean[f])) unknown.push_back(std::uint32_t(f));
  mean = nearest_known(g, blocks, nullptr, mean);
  std::vector<double> square(n);
  for (std::size_t f = 0; f < n; ++f) square[f] = mean[f] * mean[f];
  // The two spreads side by side, each on half the cores.
  const int half = std::max(1, thread_count() / 2);
  on_threads(2, [&](int t) { jacobi(g, unknown, {}, sweeps_for(p), t == 0 ? mean : square, {}, half); });
  std::vector<double> out(n);
  for (std::size_t f = 0; f < n; ++f)
    out[f] = std::sqrt(std::max(0.0, square[f] - mean[f] * mean[f])) + 1e-3 * (largest - smallest);
  return out;
}

// The two rounds' samples, sorted, with their raw values in that order.
void merge_rounds(const std::vector<std::uint32_t>& first, const RawSdf& raw1, const std::vector<std::uint32_t>& second,
                  const RawSdf& raw2, FastSdf& out) {
  std::vector<std::pair<std::uint32_t, double>> all;
  all.reserve(first.size() + second.size());
  for (std::size_t i = 0; i < first.size(); ++i) all.push_back({first[i], raw1.values[i]});
  for (std::size_t i = 0; i < second.size(); ++i) all.push_back({second[i], raw2.values[i]});
  std::sort(all.begin(), all.end());
  out.raw = raw1;
  out.raw.values.clear();
  out.samples.clear();
  for (const auto& [f, v] : all) out.samples.push_back(f), out.raw.values.push_back(v);
  out.raw.rays_cast += raw2.rays_cast;
  out.raw.rays_accepted += raw2.rays_accepted;
  out.raw.missing += raw2.missing;
}

// spread_samples, leaving in `ring` each face's rings from the samples.
std::vector<std::uint32_t> spread_rings(const Adjacency& g, std::size_t count, std::vector<std::uint32_t>& ring) {
  const std::size_t n = g.size();
  constexpr std::uint32_t far = std::numeric_limits<std::uint32_t>::max();
  ring.assign(n, far);
  std::vector<std::uint32_t> queue, samples;
  queue.reserve(n);
  const auto add = [&](std::uint32_t s) {
    samples.push_back(s);
    ring[s] = 0;
    queue.assign(1, s);
    lower_rings(g, ring, queue);
  };
  for (std::size_t f = 0; f < n; ++f)
    if (ring[f] == far) add(std::uint32_t(f));  // the first face of each part
  // The farthest face next: faces by ring, each moved down to its ring as
  // it is now when it comes up (rings only fall).
  std::uint32_t top = 0;
  for (std::uint32_t r : ring) top = std::max(top, r);
  std::vector<std::vector<std::uint32_t>> by_ring(top + 1);
  for (std::size_t f = 0; f < n; ++f) by_ring[ring[f]].push_back(std::uint32_t(f));
  while (samples.size() < count && top > 0) {
    if (by_ring[top].empty()) {
      --top;
      continue;
    }
    const std::uint32_t f = by_ring[top].back();
    by_ring[top].pop_back();
    if (ring[f] == top) add(f);
    else if (ring[f] > 0) by_ring[ring[f]].push_back(f);
  }
  std::sort(samples.begin(), samples.end());
  return samples;
}

}  // namespace

std::vector<std::uint32_t> spread_samples(const Adjacency& g, std::size_t count) {
  std::vector<std::uint32_t> ring;
  return spread_rings(g, count, ring);
}

namespace {

// pick(k, count) for each block k on every core, count its share of `total`
// (by its faces); the faces it picks (the block's local numbers) mapped to
// the mesh's, block after block.
template <class Pick>
std::vector<std::uint32_t> pick_in_blocks(const CurveBlocks& blocks, std::size_t total, const Pick& pick) {
  const std::size_t m = blocks.size();
  std::vector<std::size_t> before(m + 1, 0);
  for (std::size_t k = 0; k < m; ++k) before[k + 1] = before[k] + blocks.faces[k].size();
  const auto upto = [&](std::size_t k) {
    return std::size_t(std::llround(double(total) * double(before[k]) / double(before[m])));
  };
  std::vector<std::vector<std::uint32_t>> picked(m);
  each_block(blocks, [&](std::size_t k) {
    picked[k] = pick(k, upto(k + 1) - upto(k));
    for (std::uint32_t& f : picked[k]) f = blocks.faces[k][f];
  });
  std::vector<std::uint32_t> out;
  out.reserve(total);
  for (const std::vector<std::uint32_t>& p : picked) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// The first round's samples (spread_rings) and each face's rings from them,
// block by block where the mesh is cut.
std::vector<std::uint32_t> first_samples(const Adjacency& g, const CurveBlocks& blocks, std::size_t count,
                                         std::vector<std::uint32_t>& ring) {
  if (blocks.size() == 0) return spread_rings(g, count, ring);
  ring.assign(g.size(), 0);
  std::vector<std::uint32_t> out = pick_in_blocks(blocks, count, [&](std::size_t k, std::size_t share) {
    std::vector<std::uint32_t> local;
    std::vector<std::uint32_t> picked = spread_rings(blocks.graphs[k], share, local);
    scatter(local, blocks.faces[k], ring);
    return picked;
  });
  std::sort(out.begin(), out.end());
  return out;
}

// The second round's (more_samples), block by block where the mesh is cut.
std::vector<std::uint32_t> second_samples(const Adjacency& g, const CurveBlocks& blocks,
                                          std::vector<std::uint32_t> ring, const std::vector<double>& spread,
                                          std::size_t count) {
  if (blocks.size() == 0) return more_samples(g, std::move(ring), spread, count);
  return pick_in_blocks(blocks, count, [&](std::size_t k, std::size_t share) {
    const std::vector<std::uint32_t>& faces = blocks.faces[k];
    return more_samples(blocks.graphs[k], gather(ring, faces), gather(spread, faces), share);
  });
}

// poisson_sdf on `given`, else on the face graph it builds into out.graph.
FastSdf poisson_sdf_on(const Mesh& mesh, const Adjacency* given, const SdfFastParams& p, const Context* ctx) {
  check_params(p);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  const std::size_t n = mesh.faces.size();
  FastSdf out;
  const Adjacency& g = given ? *given : out.graph;
  auto last = std::chrono::steady_clock::now();
  const auto step_done = [&](const char* name) {
    const auto now = std::chrono::steady_clock::now();
    out.steps.push_back({name, std::chrono::duration<double>(now - last).count()});
    last = now;
  };
  // Two rounds of rays on one BVH: 60% of the samples spread evenly, the
  // rest where those leave the SDF least certain (more_samples).
  // The face graph and the first round's samples, which need no BVH, are
  // made on a second thread while the BVH is built: Embree's build keeps
  // both cores busy only in part (on polygon_mesh, 32k faces, it takes 3.5
  // ms on two threads, 7 on one).  The arcs' weights, needed from the solve
  // on, are weighed by whichever thread is free first once the graph is
  // made.  On 2 cores: on polygon_mesh the BVH's (free at 5.7 ms, the
  // sampling's at 7-9 ms); on the 1.42M-face mesh, whose blocks sample on
  // every core, the sampling's (free at 0.48-0.66 s, the BVH's at
  // 0.58-0.79 s).
  const std::size_t total = std::size_t(std::ceil(p.fraction * double(n)));
  std::vector<std::uint32_t> ring, first;
  CurveBlocks blocks;
  ArcWeights weights;
  std::optional<SdfRayCaster> caster;
  std::latch graph_made(1);
  std::atomic_flag weighed;
  const auto weigh_arcs = [&] {
    if (!weighed.test_and_set()) weights = arc_weights(mesh, g);
  };
  on_threads(2, [&](int t) {
    if (t == 1) {
      if (!given) out.graph = face_neighbors(mesh, edge_topology(mesh));
      graph_made.count_down();
      blocks = curve_blocks(mesh, g, kSampleBlockFaces);
      first = first_samples(g, blocks, std::size_t(std::ceil(kFirstRound * double(total))), ring);
      weigh_arcs();
    } else {
      caster.emplace(mesh, p.sdf);
      graph_made.wait();
      weigh_arcs();
    }
  });
  step_done("graph, BVH, first samples");
  const SdfRayCaster& rays = *caster;
  const RawSdf raw1 = rays.cast(first, ctx, 0.0, 0.5);
  step_done("first rays");
  std::vector<std::uint32_t> second;
  RawSdf raw2;
  if (first.size() < total) {
    const std::vector<double> spread = uncertainty(g, blocks, p, first, raw1.values);
    second = second_samples(g, blocks, std::move(ring), spread, total - first.size());
    step_done("second samples");
    raw2 = rays.cast(second, ctx, 0.5, 0.8);
    step_done("second rays");
  }
  merge_rounds(first, raw1, second, raw2, out);

  // Only the samples whose rays found the inside are boundary values: one
  // whose rays all escaped (an open mesh) marks a region the full SDF fills
  // afterwards (fill_escaped below), and as a boundary value it would pull
  // its thick neighbours down.
  std::vector<std::uint32_t> kept, escaped;
  out.values.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < out.samples.size(); ++i) {
    if (std::isnan(out.raw.values[i])) escaped.push_back(out.samples[i]);
    else out.values[out.samples[i]] = out.raw.values[i], kept.push_back(out.samples[i]);
  }
  if (kept.empty()) {  // no ray found the inside anywhere: 0, as fill_missing
    std::fill(out.values.begin(), out.values.end(), 0.0);
    return out;
  }
  if (p.sdf.smooth) smooth_samples(g, blocks, p, out.samples, out.values);
  step_done("samples smoothed");
  if (ctx) ctx->progress(0.8, "solving the Poisson equation");

  // The unknowns: the faces of the parts that have a kept sample (those of a
  // part whose samples all escaped are filled afterwards).
  EscapedRegion region;
  on_threads(escaped.empty() ? 1 : 2, [&](int t) {
    if (t == 1) {
      region = escaped_region(g, weights, p, out.samples, escaped);
      return;
    }
    const std::vector<double> start = nearest_known(g, blocks, &weights, out.values);
    std::vector<std::int64_t> row(n, -1);
    std::vector<std::uint32_t> unknown;
    for (std::size_t f = 0; f < n; ++f)
      if (std::isnan(out.values[f]) && !std::isnan(start[f]))
        row[f] = std::int64_t(unknown.size()), unknown.push_back(std::uint32_t(f));
    out.unknowns = unknown.size();
    solve(mesh, g, p, start, unknown, row, weights, thread_count() - (escaped.empty() ? 0 : 1), out);
    // Last, with smoothing, each sample takes its neighbours' weighted mean:
    // its own value rests on its own cone of rays, theirs on the several
    // samples the solve reached them from (mannequin-devil 3.32% to 3.21% off
    // the full SDF, polygon_mesh 3.80% to 3.73%, fandisk_large 2.17% to
    // 2.04%; more sweeps, over every face, blurred where parts meet:
    // docs/BENCHMARKS.md).
    if (p.sdf.smooth) jacobi(g, kept, {}, 1, out.values, weights.weight);
  });
  step_done("solve");
  fill_escaped(mesh, g, p, region, out.values);
  step_done("escaped regions");
  return out;
}

}  // namespace

FastSdf poisson_sdf(const Mesh& mesh, const Adjacency& face_graph, const SdfFastParams& p, const Context* ctx) {
  return poisson_sdf_on(mesh, &face_graph, p, ctx);
}

FastSdf poisson_sdf(const Mesh& mesh, const SdfFastParams& p, const Context* ctx) {
  return poisson_sdf_on(mesh, nullptr, p, ctx);
}

}  // namespace cgview::sdf
