#include "sdf/sdf_rays.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <thread>

#include "sdf/curve_order.h"
#include "sdf/parallel_blocks.h"
#include "rays/gpu_ray_caster.h"
#include "rays/ray_caster.h"
#include "registry/registry.h"

namespace cgview::sdf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A ray of the cone in the face's frame: t along the axis (-n), (du, dv) in
// the plane, and its weight.
struct ConeRay {
  double axis, du, dv, weight;
};

std::vector<ConeRay> cone_rays(const SdfParams& o) {
  const double half = o.cone_angle * std::numbers::pi / 360.0;
  const double golden = 3.0 - std::sqrt(5.0);  // Vogel's spiral, as CGAL's Vogel_disk_sampling
  std::vector<ConeRay> rays;
  const auto angle = [&](int i) { return std::atan2(std::sin(half) * double(i) / o.rays, std::cos(half)); };
  const double angle1 = o.rays > 1 ? angle(1) : 1.0;
  for (int i = 0; i < o.rays; ++i) {
    const double r = double(i) / o.rays, q = i * golden * std::numbers::pi;
    const double w = o.weights == Weights::uniform ? 1.0 : 1.0 / std::max(angle(i), angle1);
    rays.push_back({std::cos(half), std::sin(half) * r * std::cos(q), std::sin(half) * r * std::sin(q), w});
  }
  return rays;
}

// A basis (u, v) of the plane of normal `in` (the face's inward normal),
// as CGAL's sdf_values takes it: Plane_3's base1 (perpendicular to `in` in
// the plane of its two largest coordinates) and base2 = in x base1.  It
// depends on the normal alone, so the cone does not turn with the corner a
// triangle is listed from, and the rays are CGAL's very rays.
void plane_basis(const Vec3& in, Vec3& u, Vec3& v) {
  const double ax = std::abs(in.x), ay = std::abs(in.y), az = std::abs(in.z);
  if (in.x == 0) u = {1, 0, 0};
  else if (in.y == 0) u = {0, 1, 0};
  else if (in.z == 0) u = {0, 0, 1};
  else if (ax <= ay && ax <= az) u = {0, -in.z, in.y};
  else if (ay <= ax && ay <= az) u = {-in.z, 0, in.x};
  else u = {-in.y, in.x, 0};
  u = normalized(u);
  v = normalized(cross(in, u));
}

// The median of sorted values, as CGAL's: the mean of the two middle ones
// when even.
double sorted_median(const std::vector<double>& x) {
  const std::size_t half = x.size() / 2;
  return x.size() % 2 ? x[half] : (x[half] + x[half - 1]) / 2.0;
}

// The median of |x - median| over sorted x, as CGAL's (the same values):
// the deviations rise outwards on each side of the median, so the two
// sides merged from it give them in order.  (On the 1.42M-face mesh the
// hits' combining took 0.67 s on one thread with two nth_elements, 0.48 s
// so.)
double sorted_median_deviation(const std::vector<double>& x, double median) {
  const std::size_t n = x.size(), half = n / 2;
  std::size_t r = std::size_t(std::lower_bound(x.begin(), x.end(), median) - x.begin());
  std::ptrdiff_t l = std::ptrdiff_t(r) - 1;
  double kth = 0, before = 0;
  for (std::size_t c = 0; c <= half; ++c) {
    before = kth;
    if (l >= 0 && (r >= n || median - x[std::size_t(l)] < x[r] - median)) kth = median - x[std::size_t(l--)];
    else kth = x[r++] - median;
  }
  return n % 2 ? kth : (kth + before) / 2.0;
}

}  // namespace

double combine_rays(std::span<const std::pair<double, double>> hits, Outliers rule, std::vector<double>& sorted) {
  double lo = -HUGE_VAL, hi = HUGE_VAL;
  if (rule != Outliers::none && hits.size() > 1) {
    // A cone's few lengths sorted by insertion, more by std::sort (which
    // alone took the combining of armadillo's hits 26 ms on one thread
    // against 21).
    sorted.clear();
    for (auto& h : hits) sorted.push_back(h.first);
    if (sorted.size() <= 32) {
      for (std::size_t i = 1; i < sorted.size(); ++i) {
        const double v = sorted[i];
        std::size_t j = i;
        for (; j > 0 && sorted[j - 1] > v; --j) sorted[j] = sorted[j - 1];
        sorted[j] = v;
      }
    } else {
      std::sort(sorted.begin(), sorted.end());
    }
    const double median = sorted_median(sorted);
    double spread;
    if (rule == Outliers::std_dev) {
      double mean = 0, var = 0;
      for (auto& h : hits) mean += h.first;
      mean /= double(hits.size());
      for (auto& h : hits) var += (h.first - mean) * (h.first - mean);
      spread = std::sqrt(var / double(hits.size()));
    } else {
      spread = 1.5 * sorted_median_deviation(sorted, median);
    }
    lo = median - spread;
    hi = median + spread;
  }
  double sum = 0, weights = 0;
  for (auto& h : hits)
    if (h.first >= lo && h.first <= hi) {
      sum += h.first * h.second;
      weights += h.second;
    }
  return weights > 0 ? sum / weights : hits[hits.size() / 2].first;
}

namespace {

// The device asked for: the parameter, else CGVIEW_SDF_RAYS; automatic unresolved.
RayDevice asked_device(const SdfParams& p) {
  if (p.device != RayDevice::automatic) return p.device;
  const char* env = std::getenv("CGVIEW_SDF_RAYS");
  const std::string e = env ? env : "";
  if (e == "cpu") return RayDevice::cpu;
  if (e == "gpu") return RayDevice::gpu;
  if (!e.empty() && e != "auto") throw InvalidInput("CGVIEW_SDF_RAYS: unknown device '" + e + "' (auto, cpu or gpu)");
  return RayDevice::automatic;
}

}  // namespace

RayDevice ray_device(const SdfParams& p) {
  const RayDevice d = asked_device(p);
  if (d != RayDevice::automatic) return d;
  return render::hardware_device_listed() ? RayDevice::gpu : RayDevice::cpu;
}

void ray_metrics(const RawSdf& raw, Metrics& metrics) { metrics["rays_on_gpu"] = raw.gpu ? 1.0 : 0.0; }

struct SdfRayCaster::State {
  const Mesh& mesh;
  SdfParams params;
  std::unique_ptr<GpuRayCaster> gpu;
  std::unique_ptr<RayCaster> caster;
  std::vector<ConeRay> cone;
  // The caster's own (a copy was 34 MB on a 1.42M-face mesh).
  const std::vector<Vec3>& normals() const { return caster ? caster->normals() : gpu->normals(); }
};

SdfRayCaster::SdfRayCaster(const Mesh& mesh, const SdfParams& o) {
  check_params(o);
  if (mesh.faces.empty()) throw InvalidInput("the mesh has no faces: the SDF is measured on faces");
  s_ = std::unique_ptr<State>(new State{mesh, o, nullptr, nullptr, cone_rays(o)});
  // The compute shader where asked, or automatically where it starts on a
  // GPU (on a software context, llvmpipe, Embree is much faster).
  std::unique_ptr<GpuRayCaster>& gpu = s_->gpu;
  if (ray_device(o) == RayDevice::gpu) {
    if (asked_device(o) == RayDevice::gpu) {
      gpu = std::make_unique<GpuRayCaster>(mesh);
    } else {
      try {
        gpu = std::make_unique<GpuRayCaster>(mesh);
        if (gpu->info().software) gpu.reset();
      } catch (const Error&) {  // no GPU context after all: Embree
      }
    }
  }
  if (!gpu) s_->caster = std::make_unique<RayCaster>(mesh);
}

SdfRayCaster::~SdfRayCaster() = default;

RawSdf SdfRayCaster::cast(std::span<const std::uint32_t> faces, const Context* ctx, double from, double to) const {
  const Mesh& mesh = s_->mesh;
  const SdfParams& o = s_->params;
  for (std::uint32_t f : faces)
    if (f >= mesh.faces.size()) throw InvalidInput("face " + std::to_string(f) + " is not in the mesh");
  const std::size_t n = faces.empty() ? mesh.faces.size() : faces.size();
  const auto listed = [&](std::size_t i) { return faces.empty() ? std::uint32_t(i) : faces[i]; };
  // The faces are cast along a Morton curve through their centroids: rays
  // from nearby faces walk the same parts of the BVH, still in the caches
  // (the raw SDF of the 1.42M-face mesh 11.1 s to 9.6 s on 2 cores; a file's
  // own order is often far from it).  The i-th cast is of the listed face
  // at[i], whose value goes to out.values[at[i]].
  const std::vector<std::uint32_t> at = face_curve_order(mesh, faces);
  const auto face_at = [&](std::size_t i) { return listed(at[i]); };
  GpuRayCaster* gpu = s_->gpu.get();
  const RayCaster* caster = s_->caster.get();
  const std::vector<Vec3>& normals = s_->normals();
  if (ctx) ctx->check_cancelled();
  const std::vector<ConeRay>& cone = s_->cone;
  const std::size_t m = cone.size();

  // Face f's centroid c and a basis (u, v) of its plane, or false for a
  // degenerate face (no direction to look in); ray k's unit direction.
  const auto frame_of = [&](std::uint32_t f, Vec3& c, Vec3& u, Vec3& v) {
    const Vec3 n = normals[f];
    if (dot(n, n) == 0) return false;
    c = face_centroid(mesh, f);
    plane_basis((-1.0) * n, u, v);
    return true;
  };
  const auto direction = [&](std::size_t k, std::uint32_t f, const Vec3& u, const Vec3& v) {
    return normalized((-cone[k].axis) * normals[f] + cone[k].du * u + cone[k].dv * v);
  };
  // A hit counts when the ray leaves the shape where it first meets the
  // surface: the face is met from behind (`normal`: the face's).
  const auto accept = [&](std::vector<std::pair<double, double>>& hits, const Vec3& d, double distance,
                          const Vec3& normal, std::size_t k) {
    if (dot(d, normal) > 0) hits.push_back({distance, cone[k].weight});
  };

  RawSdf out;
  out.values.assign(n, kNaN);
  std::atomic<std::size_t> accepted{0};
  if (!gpu) {
    parallel_blocks(n, 512, thread_count(), ctx, from, to, "casting rays", [&](std::size_t b, std::size_t e) {
      std::vector<std::pair<double, double>> hits;
      std::vector<double> scratch;
      std::size_t local_accepted = 0;
      for (std::size_t i = b; i < e; ++i) {
        const std::uint32_t f = face_at(i);
        Vec3 c, u, v;
        hits.clear();
        if (frame_of(f, c, u, v))
          for (std::size_t k = 0; k < m; ++k) {
            const Vec3 d = direction(k, f, u, v);
            if (const RayCaster::Hit h = caster->first_hit(c, d, f)) accept(hits, d, h.distance, h.normal, k);
          }
        local_accepted += hits.size();
        if (!hits.empty()) out.values[at[i]] = combine_rays(hits, o.outliers, scratch);
      }
      accepted += local_accepted;
    });
  } else {
    // Batches of faces: their frames made on the cores, their cones cast in
    // the shader (which tells the hits met from behind), the hits combined
    // on the cores.
    out.gpu = true;
    out.gpu_renderer = gpu->info().gl_renderer;
    std::vector<GpuRayCaster::ConeRay> dirs;
    for (const ConeRay& r : cone) dirs.push_back({float(r.axis), float(r.du), float(r.dv)});
    const auto f3 = [](const Vec3& a, float* out) { out[0] = float(a.x), out[1] = float(a.y), out[2] = float(a.z); };
    // Chunks of about 1M rays (the caster's batch), in a pipeline: while
    // the calling thread (the GL context's) has the shader cast chunk j, the
    // other cores accept and combine chunk j - 1's hits and make chunk
    // j + 1's frames.
    const std::size_t chunk = std::max<std::size_t>(1, (std::size_t(1) << 20) / m);
    const std::size_t chunks = (n + chunk - 1) / chunk;
    std::vector<GpuRayCaster::Frame> frames[2];
    std::vector<GpuRayCaster::FaceHit> found[2];
    const auto make_frames = [&](std::size_t j, int threads) {
      const std::size_t cb = j * chunk, ce = std::min(n, cb + chunk);
      std::vector<GpuRayCaster::Frame>& out_frames = frames[j % 2];
      out_frames.assign(ce - cb, GpuRayCaster::Frame{});
      parallel_blocks(ce - cb, 4096, threads, nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) {
          const std::uint32_t f = face_at(cb + i);
          Vec3 c, u, v;
          if (!frame_of(f, c, u, v)) continue;
          GpuRayCaster::Frame& fr = out_frames[i];
          fr.face = f;
          f3(c, fr.origin), f3(normals[f], fr.n), f3(u, fr.u), f3(v, fr.v);
        }
      });
    };
    const auto take_hits = [&](std::size_t j, int threads) {
      const std::size_t cb = j * chunk, ce = std::min(n, cb + chunk);
      const std::vector<GpuRayCaster::FaceHit>& hit = found[j % 2];
      parallel_blocks(ce - cb, 512, threads, nullptr, 0, 0, "", [&](std::size_t b, std::size_t e) {
        std::vector<std::pair<double, double>> hits;
        std::vector<double> scratch;
        std::size_t local_accepted = 0;
        for (std::size_t i = b; i < e; ++i) {
          // The shader has made accept's test (a degenerate face's frame
          // met nothing).
          hits.clear();
          for (std::size_t k = 0; k < m; ++k)
            if (const GpuRayCaster::FaceHit& h = hit[i * m + k]; h.behind())
              hits.push_back({h.distance, cone[k].weight});
          local_accepted += hits.size();
          if (!hits.empty()) out.values[at[cb + i]] = combine_rays(hits, o.outliers, scratch);
        }
        accepted += local_accepted;
      });
    };
    const int helpers = std::max(1, thread_count() - 1);
    make_frames(0, thread_count());
    for (std::size_t j = 0; j < chunks; ++j) {
      if (ctx) {
        ctx->check_cancelled();
        ctx->progress(from + (to - from) * double(j * chunk) / double(n), "casting rays on the GPU");
      }
      on_threads(j > 0 || j + 1 < chunks ? 2 : 1, [&](int t) {
        if (t == 0) {
          const auto start = std::chrono::steady_clock::now();
          gpu->cone_hits(frames[j % 2], dirs, found[j % 2]);
          out.gpu_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          return;
        }
        if (j > 0) take_hits(j - 1, helpers);
        if (j + 1 < chunks) make_frames(j + 1, helpers);
      });
    }
    if (chunks > 0) take_hits(chunks - 1, thread_count());
  }
  out.rays_cast = n * m;
  out.rays_accepted = accepted;
  out.missing =
      std::size_t(std::count_if(out.values.begin(), out.values.end(), [](double x) { return std::isnan(x); }));
  return out;
}

RawSdf raw_sdf(const Mesh& mesh, const SdfParams& o, std::span<const std::uint32_t> faces, const Context* ctx,
               double from, double to) {
  return SdfRayCaster(mesh, o).cast(faces, ctx, from, to);
}

RawSdf raw_sdf(const Mesh& mesh, const SdfParams& o, Adjacency& face_graph, const Context* ctx, double from,
               double to) {
  RawSdf raw;
  on_threads(2, [&](int t) {
    if (t == 1) face_graph = face_neighbors(mesh, edge_topology(mesh));
    else raw = raw_sdf(mesh, o, {}, ctx, from, to);
  });
  return raw;
}

void fill_missing(const Mesh& mesh, const Adjacency& graph, std::vector<double>& values) {
  double smallest = HUGE_VAL;
  for (double v : values)
    if (!std::isnan(v)) smallest = std::min(smallest, v);
  if (smallest == HUGE_VAL) smallest = 0;  // no face has a value
  std::vector<std::size_t> still;
  // As CGAL's check_missing_sdf_values: the faces in order, each without a
  // value given its neighbours' mean as they are then (one filled before it
  // counts), then those still without one the smallest value.
  for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
    if (!std::isnan(values[f])) continue;
    double sum = 0;
    int count = 0;
    for (const std::uint32_t* g = graph.begin(f); g != graph.end(f); ++g)
      if (!std::isnan(values[*g])) sum += values[*g], ++count;
    if (count) values[f] = sum / count;
    else still.push_back(f);
  }
  for (std::size_t f : still) values[f] = smallest;
}

std::vector<double> normalize_linear(const std::vector<double>& values) {
  if (values.empty()) return {};
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  std::vector<double> out(values.size(), 0.5);
  if (*hi > *lo)
    for (std::size_t i = 0; i < values.size(); ++i) out[i] = (values[i] - *lo) / (*hi - *lo);
  return out;
}

void postprocess(const Mesh& mesh, const Adjacency& graph, std::vector<double>& values, const SdfParams& p,
                 const Context& ctx) {
  fill_missing(mesh, graph, values);
  if (p.smooth) bilateral_smooth(mesh, graph, values, p.window, &ctx);
}

void warn_missing(const RawSdf& raw, std::vector<std::string>& warnings, std::string_view fill) {
  if (raw.missing)
    warnings.push_back(std::to_string(raw.missing) + " of " + std::to_string(raw.values.size()) +
                       " faces had no ray that found the inside (an open or degenerate mesh): they take " +
                       std::string(fill));
}

double pearson(std::span<const double> a, std::span<const double> b) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n == 0) return 0;
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i) ma += a[i], mb += b[i];
  ma /= double(n), mb /= double(n);
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0.0;
}

}  // namespace cgview::sdf
