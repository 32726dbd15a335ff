#include "sdf/sdf_poisson.h"

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "filters/vertex_curvatures.h"

namespace cgview::sdf {
namespace {

std::uint64_t spread_bits(std::uint64_t x) {  // 21 bits to every third of 63
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

Vec3 centroid(const Mesh& m, std::size_t f) {
  const Tri& t = m.faces[f];
  return (m.positions[t[0]] + m.positions[t[1]] + m.positions[t[2]]) / 3.0;
}

// Connected part of each face in the dual graph.
std::vector<std::uint32_t> face_components(const Adjacency& g, std::uint32_t& count) {
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> part(g.size(), none), stack;
  count = 0;
  for (std::size_t s = 0; s < g.size(); ++s) {
    if (part[s] != none) continue;
    part[s] = count;
    stack.assign(1, std::uint32_t(s));
    while (!stack.empty()) {
      const std::uint32_t f = stack.back();
      stack.pop_back();
      for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h)
        if (part[*h] == none) part[*h] = count, stack.push_back(*h);
    }
    ++count;
  }
  return part;
}

// Each face's nearest known face's value (breadth-first from all of them):
// the conjugate gradients' start.
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
      length += norm(centroid(mesh, f) - centroid(mesh, *h));
  const double l = arcs ? length / double(arcs) : 0.0;
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    out[f] = weight * l * l * (k.mean[t[0]] + k.mean[t[1]] + k.mean[t[2]]) / 3.0;
  }
  return out;
}

// spread_samples, with the connected parts (face_components) given: they
// are found once for the samples and the solve.
std::vector<std::uint32_t> spread_over_parts(const Mesh& mesh, const std::vector<std::uint32_t>& part,
                                             std::uint32_t parts, std::size_t count) {
  const std::size_t n = mesh.faces.size();
  count = std::clamp<std::size_t>(count, 1, n);
  BBox box;
  for (const Vec3& p : mesh.positions) box.add(p);
  const Vec3 size = box.size();
  const double extent = std::max({size.x, size.y, size.z, 1e-300});
  std::vector<std::pair<std::uint64_t, std::uint32_t>> order(n);
  for (std::size_t f = 0; f < n; ++f) {
    const Vec3 q = (centroid(mesh, f) - box.min) / extent * double((1 << 21) - 1);
    order[f] = {
        spread_bits(std::uint64_t(q.x)) | spread_bits(std::uint64_t(q.y)) << 1 | spread_bits(std::uint64_t(q.z)) << 2,
        std::uint32_t(f)};
  }
  std::sort(order.begin(), order.end());
  std::vector<std::uint32_t> samples;
  samples.reserve(count);
  for (std::size_t j = 0; j < count; ++j)
    samples.push_back(order[std::size_t((double(j) + 0.5) * double(n) / double(count))].second);
  std::vector<char> covered(parts, 0);
  for (std::uint32_t f : samples) covered[part[f]] = 1;
  for (std::size_t f = 0; f < n; ++f)
    if (!covered[part[f]]) covered[part[f]] = 1, samples.push_back(std::uint32_t(f));
  std::sort(samples.begin(), samples.end());
  samples.erase(std::unique(samples.begin(), samples.end()), samples.end());
  return samples;
}

}  // namespace

std::vector<std::uint32_t> spread_samples(const Mesh& mesh, const Adjacency& g, std::size_t count) {
  std::uint32_t parts = 0;
  const std::vector<std::uint32_t> part = face_components(g, parts);
  return spread_over_parts(mesh, part, parts, count);
}

FastSdf poisson_sdf(const Mesh& mesh, const Adjacency& g, const SdfFastParams& p, const Context* ctx) {
  check_params(p);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  const std::size_t n = mesh.faces.size();
  std::uint32_t parts = 0;
  const std::vector<std::uint32_t> part = face_components(g, parts);
  FastSdf out;
  out.samples = spread_over_parts(mesh, part, parts, std::size_t(std::ceil(p.fraction * double(n))));
  out.raw = raw_sdf(mesh, p.sdf, out.samples, ctx, 0.0, 0.8);
  // A sample whose rays all escaped (an open mesh) takes the smallest sampled
  // value, as fill_missing gives the full SDF's faces inside such a region:
  // left unknown, it would take its thick neighbours' values instead.
  double smallest = HUGE_VAL;
  for (double v : out.raw.values)
    if (!std::isnan(v)) smallest = std::min(smallest, v);
  if (smallest == HUGE_VAL) smallest = 0;  // no ray found the inside anywhere: 0, as fill_missing
  out.values.assign(n, std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0; i < out.samples.size(); ++i)
    out.values[out.samples[i]] = std::isnan(out.raw.values[i]) ? smallest : out.raw.values[i];
  if (p.sdf.smooth) bilateral_smooth(g, out.values, p.sdf.window, nullptr, out.samples);
  if (ctx) ctx->progress(0.8, "solving the Poisson equation");

  // Every part has a sample with a value: every other face is an unknown.
  std::vector<std::int64_t> row(n, -1);
  std::vector<std::uint32_t> unknown;
  for (std::size_t f = 0; f < n; ++f)
    if (std::isnan(out.values[f])) row[f] = std::int64_t(unknown.size()), unknown.push_back(std::uint32_t(f));
  out.unknowns = unknown.size();
  if (unknown.empty()) return out;
  const std::vector<double> rhs_guide = guidance(mesh, g, p.curvature_weight);

  if (p.solver == Solver::diffusion) {
    // Samples are about 1 / sqrt(fraction) rings apart, and t sweeps spread
    // a value over about sqrt(t) rings: 0.8 / fraction sweeps reach between
    // samples without averaging over the next ones (the constant measured
    // on four meshes at 5-40%, docs/DESIGN.md).  The cap bounds the time at
    // fractions below 0.3%.
    const int sweeps = int(std::min(256.0, std::ceil(0.8 / p.fraction)));
    std::vector<double> x = nearest_known(g, out.values), next = x;
    for (int s = 0; s < sweeps; ++s) {
      for (std::uint32_t f : unknown) {
        double sum = -rhs_guide[f];
        for (const std::uint32_t* h = g.begin(f); h != g.end(f); ++h) sum += x[*h];
        next[f] = sum / double(g.degree(f));
      }
      x.swap(next);
    }
    out.values = std::move(x);
    out.iterations = sweeps;
    return out;
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
    const std::vector<double> start = nearest_known(g, out.values);
    Eigen::VectorXd x0(Eigen::Index(unknown.size()));
    for (std::size_t r = 0; r < unknown.size(); ++r) x0[Eigen::Index(r)] = start[unknown[r]];
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg(A);
    cg.setTolerance(1e-6);  // relative residual: far below the SDF's own noise
    x = cg.solveWithGuess(b, x0);
    out.iterations = int(cg.iterations());
  }
  for (std::size_t r = 0; r < unknown.size(); ++r) out.values[unknown[r]] = x[Eigen::Index(r)];
  return out;
}

}  // namespace cgview::sdf
