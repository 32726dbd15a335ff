#include "render/views.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <utility>

#include "core/errors.h"
#include "render/renderer_pool.h"

namespace cgview::render {

namespace {

std::vector<Vec3> fibonacci(int n) {
  std::vector<Vec3> out(n);
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1.0 - (2.0 * i + 1.0) / n;  // cell centres in y
    const double r = std::sqrt(std::max(0.0, 1.0 - y * y));
    out[i] = {r * std::cos(golden * i), y, r * std::sin(golden * i)};
  }
  return out;
}

std::vector<Vec3> icosahedron(int at_least) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& p : v) p = normalized(p);
  while (int(v.size()) < at_least) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(normalized(v[a] + v[b]));
      return mid[key] = int(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    g.reserve(f.size() * 4);
    for (const auto& [a, b, c] : f) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.push_back({a, ab, ca});
      g.push_back({b, bc, ab});
      g.push_back({c, ca, bc});
      g.push_back({ab, bc, ca});
    }
    f = std::move(g);
  }
  return v;
}

}  // namespace

std::vector<Vec3> sphere_directions(int n, SphereSampling sampling) {
  if (n < 1) throw InvalidInput("views must be >= 1, got " + std::to_string(n));
  if (n > 100000) throw InvalidInput("views must be <= 100000, got " + std::to_string(n));
  return sampling == SphereSampling::fibonacci ? fibonacci(n) : icosahedron(n);
}

std::vector<ViewCapture> capture_views(Renderer& renderer, const Mesh& mesh, const ViewsParams& params) {
  check_image_size(params.width, params.height);
  const std::vector<Vec3> dirs = sphere_directions(params.views, params.sampling);
  const BBox box = bounding_box(mesh);
  std::vector<CameraMatrices> cameras;
  cameras.reserve(dirs.size());
  for (const Vec3& d : dirs) cameras.push_back(orthographic_view(d, box, params.width, params.height));
  return capture_cameras(renderer, mesh, cameras, params.contexts, {.face_ids = params.face_ids});
}

int automatic_contexts(const Renderer& renderer) { return renderer.info().software ? 2 : 1; }

std::vector<ViewCapture> capture_cameras(Renderer& renderer, const Mesh& mesh,
                                         const std::vector<CameraMatrices>& cameras, int contexts,
                                         const CaptureOptions& options) {
  if (contexts < 1 || contexts > 64) throw InvalidInput("contexts must be in [1, 64], got " + std::to_string(contexts));
  const int n = std::min<int>(contexts, int(cameras.size()));
  if (n <= 1) return renderer.capture(mesh, cameras, options);

  // Contiguous blocks of views, one per context; the first on this thread.
  const GlPlatform platform = renderer.info().platform == "surfaceless" ? GlPlatform::surfaceless : GlPlatform::device;
  std::vector<std::vector<ViewCapture>> parts(n);
  std::vector<std::exception_ptr> errors(n);
  auto block = [&](int k) {
    const std::size_t a = cameras.size() * k / n, b = cameras.size() * (k + 1) / n;
    return std::vector<CameraMatrices>(cameras.begin() + a, cameras.begin() + b);
  };
  std::vector<std::thread> threads;
  for (int k = 1; k < n; ++k)
    threads.emplace_back([&, k] {
      // The extra contexts come from the process's pool (renderer_pool.h);
      // one whose capture threw is given up.
      RendererPool& pool = shared_pool(platform);
      std::unique_ptr<Renderer> extra;
      try {
        extra = pool.take();
      } catch (...) {  // no context started: nothing to give back
        errors[k] = std::current_exception();
        return;
      }
      try {
        parts[k] = extra->capture(mesh, block(k), options);
        pool.give_back(std::move(extra));
      } catch (...) {
        errors[k] = std::current_exception();
        pool.give_back(nullptr);
      }
    });
  try {
    parts[0] = renderer.capture(mesh, block(0), options);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (auto& t : threads) t.join();
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  std::vector<ViewCapture> out;
  out.reserve(cameras.size());
  for (auto& p : parts)
    for (auto& v : p) out.push_back(std::move(v));
  return out;
}

}  // namespace cgview::render
