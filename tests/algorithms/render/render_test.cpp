// The offscreen renderer, on whatever EGL platform starts (llvmpipe here and
// in CI): exact answers on a cube, depth against the surface, face ids
// against CGAL's ray shooting, a stored reference image, bad input, leaks
// over 1000 renders, and renderers on several threads.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <optional>
#include <thread>
#include <tuple>

#include <unistd.h>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "render/renderer.h"
#include "render/renderer_pool.h"
#include "render/views.h"
#include "test_support.h"

using namespace cgview;
using namespace cgview::render;

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

struct TriangleTree {
  Triangles triangles;
  Tree tree;
  explicit TriangleTree(const Mesh& m) {
    for (const Tri& t : m.faces) {
      const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
      triangles.emplace_back(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z), K::Point_3(c.x, c.y, c.z));
    }
    tree.insert(triangles.begin(), triangles.end());
    tree.accelerate_distance_queries();
  }
  // The first face a ray hits, or kNoFace.
  std::uint32_t shoot(const Ray& r) const {
    const K::Ray_3 ray(K::Point_3(r.origin.x, r.origin.y, r.origin.z),
                       K::Vector_3(r.direction.x, r.direction.y, r.direction.z));
    const auto hit = tree.first_intersected_primitive(ray);
    return hit ? std::uint32_t(*hit - triangles.begin()) : kNoFace;
  }
  double distance(Vec3 p) const { return std::sqrt(tree.squared_distance(K::Point_3(p.x, p.y, p.z))); }
  // Where a ray first meets the mesh, if it does.
  std::optional<Vec3> first_point(const Ray& r) const {
    const K::Ray_3 ray(K::Point_3(r.origin.x, r.origin.y, r.origin.z),
                       K::Vector_3(r.direction.x, r.direction.y, r.direction.z));
    const auto hit = tree.first_intersection(ray);
    if (!hit) return std::nullopt;
    const K::Point_3* p = boost::get<K::Point_3>(&hit->first);  // CGAL 5.5: a boost::variant
    if (!p) return std::nullopt;                                // along a triangle's plane
    return Vec3{p->x(), p->y(), p->z()};
  }
};

// One renderer for the suite: starting a context costs tens of milliseconds.
Renderer& shared_renderer() {
  static Renderer r;
  return r;
}

long rss_kb() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  f >> pages >> resident;
  return resident * (sysconf(_SC_PAGESIZE) / 1024);
}

}  // namespace

TEST(RenderContext, StartsAndLogsSoftwareOnce) {
  std::mutex m;
  std::vector<std::string> messages;
  set_render_log([&](const std::string& s) {
    std::lock_guard lock(m);
    messages.push_back(s);
  });
  {
    Renderer a, b;
    EXPECT_FALSE(a.info().gl_renderer.empty());
    EXPECT_FALSE(a.info().platform.empty());
    EXPECT_EQ(a.info().platform, b.info().platform);
    // OpenGL 3.3 or later.
    EXPECT_GE(std::atof(a.info().gl_version.c_str()), 3.3 - 1e-9) << a.info().gl_version;
    std::printf("renderer: %s / %s on %s%s\n", a.info().gl_vendor.c_str(), a.info().gl_renderer.c_str(),
                a.info().platform.c_str(), a.info().software ? " (software)" : "");
    for (const auto& s : a.info().attempts) std::printf("  tried %s\n", s.c_str());
  }
  set_render_log(nullptr);
  // At most once per process (earlier tests may have sent it already).
  EXPECT_LE(messages.size(), 1u);
}

TEST(RenderContext, PlatformSetting) {
  EXPECT_EQ(parse_gl_platform("surfaceless"), GlPlatform::surfaceless);
  EXPECT_EQ(parse_gl_platform("device"), GlPlatform::device);
  EXPECT_EQ(parse_gl_platform("auto"), GlPlatform::automatic);
  try {
    parse_gl_platform("x11", "--gl-platform");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("--gl-platform"), std::string::npos);
  }
  // Each platform that this machine offers starts on its own, or fails with
  // an Error naming what it tried.
  for (GlPlatform p : {GlPlatform::surfaceless, GlPlatform::device}) {
    try {
      Renderer r(p);
      const Mesh cube = test::box();
      RenderParams params;
      params.width = params.height = 32;
      params.silhouette = true;
      const RenderResult out = r.render(cube, params);
      long inside = 0;
      for (auto s : out.silhouette) inside += s;
      EXPECT_GT(inside, 0) << to_string(p);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("EGL"), std::string::npos) << e.what();
    }
  }
}

// A platform that fails to start gives way to the next one; when all fail,
// the error names each attempt.
TEST(RenderContext, FallsBackWhenAPlatformFailsToStart) {
  set_egl_fault_injection([](const std::string& name) { return name == "surfaceless"; });
  try {
    Renderer r;
    EXPECT_NE(r.info().platform, "surfaceless");
    bool refused = false;
    for (const auto& a : r.info().attempts) refused |= a.find("surfaceless: refused") == 0;
    // (On a GPU machine the hardware device comes first and surfaceless is never tried.)
    if (r.info().software) {
      EXPECT_TRUE(refused);
    }
    const Mesh cube = test::box();
    RenderParams p;
    p.width = p.height = 16;
    p.silhouette = true;
    long inside = 0;
    for (auto s : r.render(cube, p).silhouette) inside += s;
    EXPECT_GT(inside, 0);
  } catch (const Error& e) {
    // No other platform here: the message says why surfaceless was given up.
    EXPECT_NE(std::string(e.what()).find("surfaceless: refused"), std::string::npos) << e.what();
  }
  set_egl_fault_injection([](const std::string&) { return true; });
  try {
    Renderer r;
    ADD_FAILURE() << "started " << r.info().platform << " although every platform fails";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no EGL platform could start"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("refused by fault injection"), std::string::npos) << e.what();
  }
  set_egl_fault_injection(nullptr);
  Renderer again;  // and nothing was left broken
  EXPECT_FALSE(again.info().gl_renderer.empty());
}

TEST(RenderCamera, ProjectAndUnprojectInvert) {
  const BBox box = bounding_box(test::torus());
  for (Projection kind : {Projection::perspective, Projection::orthographic}) {
    Camera cam;
    cam.projection = kind;
    cam.azimuth = 37;
    cam.elevation = -25;
    const CameraMatrices m = resolve_camera(cam, box, 320, 200);
    const Vec3 p{0.3, -0.2, 0.1};
    const Vec3 s = m.project(p);
    const Vec3 q = m.unproject(s.x, s.y, s.z);
    EXPECT_LT(norm(q - p), 1e-9);
    const Ray r = m.ray(s.x, s.y);
    EXPECT_LT(norm(cross(p - r.origin, r.direction)), 1e-9);
  }
}

TEST(RenderViews, SphereDirections) {
  for (int n : {1, 7, 100}) {
    const auto d = sphere_directions(n);
    ASSERT_EQ(int(d.size()), n);
    Vec3 mean{};
    for (const Vec3& v : d) {
      EXPECT_NEAR(norm(v), 1.0, 1e-12);
      mean += v;
    }
    if (n == 100) {
      EXPECT_LT(norm(mean / 100.0), 0.02);
    }
  }
  EXPECT_EQ(sphere_directions(12, SphereSampling::icosahedron).size(), 12u);
  EXPECT_EQ(sphere_directions(13, SphereSampling::icosahedron).size(), 42u);
  EXPECT_EQ(sphere_directions(100, SphereSampling::icosahedron).size(), 162u);
  EXPECT_THROW(sphere_directions(0), InvalidInput);
}

// A unit cube seen along an axis, orthographically: a square of 1/pixel_size
// pixels a side.
TEST(RenderViews, CubeSilhouetteAlongAnAxis) {
  const Mesh cube = test::box();
  const BBox box = bounding_box(cube);
  for (int size : {64, 256, 300}) {
    for (Vec3 dir : {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{0, -1, 0}}) {
      const CameraMatrices cam = orthographic_view(dir, box, size, size);
      const auto views = shared_renderer().capture(cube, {cam});
      ASSERT_EQ(views.size(), 1u);
      long count = 0;
      for (auto s : views[0].silhouette) count += s;
      const double side = 1.0 / cam.pixel_size_at(0);
      // Within one pixel of border all around.
      EXPECT_NEAR(double(count), side * side, 4 * side + 4) << "size " << size << " dir " << dir.x << dir.y << dir.z;
    }
  }
}

TEST(RenderViews, DepthUnprojectsOntoTheSurface) {
  for (const Mesh& mesh : {test::torus(), test::uv_sphere(1.5, 24, 48)}) {
    const TriangleTree tree(mesh);
    ViewsParams params;
    params.views = 6;
    params.width = params.height = 128;
    Renderer& r = shared_renderer();
    const auto views = capture_views(r, mesh, params);
    ASSERT_EQ(views.size(), 6u);
    for (const ViewCapture& v : views) {
      const double pixel = v.camera.pixel_size_at(0);
      double worst = 0;
      long n = 0;
      for (int y = 0; y < v.camera.height; ++y)
        for (int x = 0; x < v.camera.width; ++x) {
          const std::size_t i = std::size_t(y) * v.camera.width + x;
          if (!v.silhouette[i]) continue;
          const Vec3 p = v.camera.unproject(x + 0.5, y + 0.5, v.depth[i]);
          worst = std::max(worst, tree.distance(p));
          ++n;
        }
      EXPECT_GT(n, 100);
      EXPECT_LT(worst, pixel) << "pixel size " << pixel;
    }
  }
}

// Back depth: where each pixel's ray leaves the mesh, against CGAL's AABB
// tree shooting the ray backwards from beyond the mesh; the silhouette and
// front depth stay those of a plain capture, bit for bit.
TEST(RenderViews, BackDepthIsWhereEachPixelsRayLeavesTheMesh) {
  const std::vector<Mesh> meshes = {test::torus(), test::uv_sphere(1.5, 24, 48),
                                    read_mesh(test::sample("elephant.off"))};
  for (const Mesh& mesh : meshes) {
    const TriangleTree tree(mesh);
    const BBox box = bounding_box(mesh);
    std::vector<CameraMatrices> cams;
    for (const Vec3& d : sphere_directions(5)) cams.push_back(orthographic_view(d, box, 96, 96));
    const auto plain = shared_renderer().capture(mesh, cams);
    const auto both = capture_cameras(shared_renderer(), mesh, cams, 2, {.back_depth = true});
    ASSERT_EQ(both.size(), cams.size());
    long n = 0, far = 0;
    for (std::size_t v = 0; v < cams.size(); ++v) {
      const ViewCapture& c = both[v];
      EXPECT_EQ(c.silhouette, plain[v].silhouette) << v;
      EXPECT_EQ(c.depth, plain[v].depth) << v;
      EXPECT_TRUE(plain[v].back_depth.empty());
      ASSERT_EQ(c.back_depth.size(), c.depth.size());
      const double pixel = c.camera.pixel_size_at(0);
      const Vec3 dir = c.camera.forward();
      for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) {
          const std::size_t i = std::size_t(y) * 96 + x;
          if (!c.silhouette[i]) {
            EXPECT_EQ(c.back_depth[i], 1.f);
            continue;
          }
          EXPECT_GE(c.back_depth[i], c.depth[i]);
          const Vec3 exit = c.camera.unproject(x + 0.5, y + 0.5, c.back_depth[i]);
          const Vec3 beyond = c.camera.unproject(x + 0.5, y + 0.5, 1.f) + dir * box.diagonal();
          const std::optional<Vec3> hit = tree.first_point(Ray{beyond, dir * -1.0});
          if (!hit) continue;  // grazing a silhouette edge
          ++n;
          // Depth is exact along the ray; a pixel's centre may fall just off
          // a triangle that a GL sample covers, near the outline.
          if (norm(*hit - exit) > pixel) ++far;
        }
    }
    EXPECT_GT(n, 1000);
    EXPECT_LT(double(far), 0.01 * double(n)) << far << " of " << n << " pixels' exits more than a pixel from CGAL's";
  }
  EXPECT_THROW(
      shared_renderer().capture(test::torus(), {orthographic_view({0, 0, 1}, bounding_box(test::torus()), 32, 32)},
                                {.face_ids = true, .back_depth = true}),
      InvalidInput);
}

TEST(RenderViews, FaceIdsAgreeWithAabbTreeRayShooting) {
  const std::vector<Mesh> meshes = {test::torus(), test::uv_sphere(), read_mesh(test::sample("elephant.off"))};
  for (const Mesh& mesh : meshes) {
    const TriangleTree tree(mesh);
    ViewsParams params;
    params.views = 5;
    params.width = params.height = 96;
    params.face_ids = true;
    const auto views = capture_views(shared_renderer(), mesh, params);
    long both = 0, agree = 0, only_one = 0;
    for (const ViewCapture& v : views)
      for (int y = 0; y < v.camera.height; ++y)
        for (int x = 0; x < v.camera.width; ++x) {
          const std::size_t i = std::size_t(y) * v.camera.width + x;
          const std::uint32_t cpu = tree.shoot(v.camera.ray(x + 0.5, y + 0.5));
          const std::uint32_t gpu = v.face_ids[i];
          EXPECT_EQ(gpu == kNoFace, v.silhouette[i] == 0);
          if (cpu == kNoFace && gpu == kNoFace) continue;
          if (cpu == kNoFace || gpu == kNoFace) {
            ++only_one;
            continue;
          }
          ++both;
          agree += cpu == gpu;
        }
    ASSERT_GT(both, 1000);
    // Pixels whose centre lies on a shared edge may go either way.
    EXPECT_GT(double(agree) / both, 0.99) << agree << " of " << both;
    EXPECT_LT(double(only_one) / both, 0.01) << only_one;
  }
}

namespace {

RenderParams reference_params() {
  RenderParams p;
  p.width = 160;
  p.height = 120;
  p.mode = RenderMode::smooth;
  p.camera.azimuth = 30;
  p.camera.elevation = 35;
  return p;
}

}  // namespace

// A render against tests/data/render/torus_smooth.png.  CGVIEW_UPDATE_REFERENCE=1 rewrites it.
TEST(RenderImage, MatchesTheStoredReference) {
  const Mesh torus = test::torus();
  const RenderResult out = shared_renderer().render(torus, reference_params());
  const std::filesystem::path ref = std::filesystem::path(CGVIEW_RENDER_DATA_DIR) / "torus_smooth.png";
  if (std::getenv("CGVIEW_UPDATE_REFERENCE")) {
    std::ofstream(ref, std::ios::binary) << encode_png(out.color);
    GTEST_SKIP() << "wrote " << ref;
  }
  std::ifstream f(ref, std::ios::binary);
  ASSERT_TRUE(f) << ref << " is missing (run with CGVIEW_UPDATE_REFERENCE=1)";
  const std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  const Image expected = decode_png(bytes);
  ASSERT_EQ(expected.width, out.color.width);
  ASSERT_EQ(expected.height, out.color.height);
  double sum = 0;
  long big = 0;
  for (std::size_t i = 0; i < expected.rgba.size(); ++i) {
    const int d = std::abs(int(expected.rgba[i]) - int(out.color.rgba[i]));
    sum += d;
    if (d > 16) ++big;
  }
  const double pixels = double(expected.width) * expected.height;
  EXPECT_LT(sum / expected.rgba.size(), 2.0) << "mean absolute difference, of 255";
  EXPECT_LT(big / pixels, 0.01) << big << " channels differ by more than 16";
}

TEST(RenderImage, EveryModeDrawsTheMesh) {
  const Mesh torus = test::torus();
  for (const char* name : {"points", "wireframe", "flat", "smooth", "toon"}) {
    RenderParams p = reference_params();
    p.mode = parse_render_mode(name);
    p.silhouette = true;
    const RenderResult out = shared_renderer().render(torus, p);
    long changed = 0, inside = 0;
    for (std::size_t i = 0; i < out.color.rgba.size(); i += 4)
      changed += out.color.rgba[i] != 255 || out.color.rgba[i + 1] != 255 || out.color.rgba[i + 2] != 255;
    for (auto s : out.silhouette) inside += s;
    EXPECT_GT(changed, 100) << name;
    EXPECT_GT(inside, 100) << name;
    EXPECT_STREQ(to_string(p.mode), name);
  }
}

TEST(RenderImage, FieldSkeletonAndSeveralMeshes) {
  const Mesh sphere = test::uv_sphere();
  ScalarField height{"height", Location::vertex, ColorHint::standard, {}};
  for (const Vec3& p : sphere.positions) height.values.push_back(float(p.y));
  ScalarField per_face{"index", Location::face, ColorHint::categorical, {}};
  for (std::size_t f = 0; f < sphere.faces.size(); ++f) per_face.values.push_back(float(f % 7));
  Skeleton skel;
  skel.nodes = {{0, -1.2, 0}, {0, 1.2, 0}};
  skel.edges = {{0, 1}};

  RenderParams p = reference_params();
  p.camera.azimuth = 0;
  p.camera.elevation = 0;
  const Image plain = shared_renderer().render(sphere, p).color;
  RenderItem item{&sphere, &height, &skel};
  const Image coloured = shared_renderer().render({item}, p).color;
  RenderItem faces_item{&sphere, &per_face};
  const Image by_face = shared_renderer().render({faces_item}, p).color;
  long differ = 0, differ_face = 0;
  for (std::size_t i = 0; i < plain.rgba.size(); ++i) {
    differ += plain.rgba[i] != coloured.rgba[i];
    differ_face += plain.rgba[i] != by_face.rgba[i];
  }
  EXPECT_GT(differ, 1000);
  EXPECT_GT(differ_face, 1000);
  // The skeleton is drawn over the sphere down the middle column: red there.
  // The line lies on the boundary between the two middle columns.
  const int y = p.height / 2;
  int red = 0;
  for (int x = p.width / 2 - 1; x <= p.width / 2; ++x) {
    const std::uint8_t* px = &coloured.rgba[(std::size_t(y) * p.width + x) * 4];
    red += px[0] > 150 && px[1] < 80;
  }
  EXPECT_GE(red, 1);

  // Two meshes: face ids of the second start after the first's faces.
  const Mesh a = test::box({-3, 0, 0}, {-2, 1, 1}), b = test::box({2, 0, 0}, {3, 1, 1});
  p.face_ids = true;
  p.camera.elevation = 10;
  const RenderResult two = shared_renderer().render({RenderItem{&a}, RenderItem{&b}}, p);
  bool seen_a = false, seen_b = false;
  for (std::uint32_t id : two.face_ids) {
    if (id == kNoFace) continue;
    ASSERT_LT(id, 24u);
    (id < 12 ? seen_a : seen_b) = true;
  }
  EXPECT_TRUE(seen_a);
  EXPECT_TRUE(seen_b);

  // A field of the wrong length is refused, naming the field.
  ScalarField wrong{"wrong", Location::vertex, ColorHint::standard, {1, 2, 3}};
  RenderItem bad{&sphere, &wrong};
  try {
    shared_renderer().render({bad}, p);
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("field"), std::string::npos) << e.what();
  }
}

// The same picture from the orbit camera and from its matrices given in full;
// a point cloud (no faces) is drawn as points.
TEST(RenderImage, FullMatricesAndPointClouds) {
  const Mesh torus = test::torus();
  RenderParams p = reference_params();
  const RenderResult orbit = shared_renderer().render(torus, p);
  p.camera.view = orbit.camera.view;
  p.camera.projection_matrix = orbit.camera.projection;
  p.camera.azimuth = 123;  // ignored when both matrices are given
  const RenderResult full = shared_renderer().render(torus, p);
  EXPECT_EQ(full.color.rgba, orbit.color.rgba);

  Mesh cloud;
  cloud.positions = torus.positions;
  RenderParams q = reference_params();
  q.silhouette = true;
  const RenderResult points = shared_renderer().render(cloud, q);
  long inside = 0;
  for (auto s : points.silhouette) inside += s;
  EXPECT_GT(inside, 100);
}

TEST(RenderInput, BadSizesAndModes) {
  const Mesh cube = test::box();
  for (auto [w, h, name] : {std::tuple{0, 10, "width"}, std::tuple{10, 0, "height"}, std::tuple{8193, 10, "width"},
                            std::tuple{10, 9000, "height"}, std::tuple{-5, 10, "width"}}) {
    RenderParams p;
    p.width = w;
    p.height = h;
    try {
      shared_renderer().render(cube, p);
      FAIL() << w << "x" << h;
    } catch (const InvalidInput& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
    }
  }
  try {
    parse_render_mode("phong");
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("mode"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("phong"), std::string::npos);
  }
  Mesh empty;
  EXPECT_THROW(shared_renderer().render(empty, RenderParams{}), InvalidInput);
  RenderParams p;
  p.camera.elevation = 120;
  EXPECT_THROW(shared_renderer().render(cube, p), InvalidInput);
}

// 1000 renders: no GL object left behind, and resident memory flat after warm-up.
TEST(RenderResources, ThousandRendersDoNotGrow) {
  Renderer r;
  const Mesh sphere = test::uv_sphere();
  ScalarField height{"height", Location::face, ColorHint::standard, std::vector<float>(sphere.num_faces(), 1.f)};
  RenderItem item{&sphere, &height};
  RenderParams p;
  p.width = 96;
  p.height = 64;
  p.depth = p.face_ids = true;
  for (int i = 0; i < 50; ++i) r.render({item}, p);
  const GlObjectCounts live = r.live_objects(), alive = r.gl_objects_alive();
  const long rss0 = rss_kb();
  for (int i = 0; i < 1000; ++i) {
    p.mode = RenderMode(i % 5);
    p.camera.azimuth = i;
    r.render({item}, p);
  }
  const long rss1 = rss_kb();
  EXPECT_EQ(r.live_objects(), live);
  EXPECT_EQ(r.gl_objects_alive(), alive);
  EXPECT_EQ(alive, live);
  // The framebuffer, its 3 renderbuffers and 5 programs stay; nothing else
  // (the back-depth buffer is made only by a capture that asks for it).
  EXPECT_EQ(live.total(), 1 + 3 + 5);
  EXPECT_LT(rss1 - rss0, 8 * 1024) << "kB grown: " << rss0 << " -> " << rss1;
  std::printf("rss %ld kB -> %ld kB after 1000 renders\n", rss0, rss1);
}

// Views split over several contexts come back in order, equal to one context's.
TEST(RenderViews, SeveralContextsGiveTheSameViews) {
  const Mesh torus = test::torus();
  ViewsParams p;
  p.views = 7;
  p.width = p.height = 48;
  p.face_ids = true;
  const auto one = capture_views(shared_renderer(), torus, p);
  p.contexts = 3;
  const auto three = capture_views(shared_renderer(), torus, p);
  ASSERT_EQ(one.size(), three.size());
  for (std::size_t v = 0; v < one.size(); ++v) {
    EXPECT_EQ(one[v].depth, three[v].depth) << v;
    EXPECT_EQ(one[v].face_ids, three[v].face_ids) << v;
  }
  p.contexts = 0;
  EXPECT_THROW(capture_views(shared_renderer(), torus, p), InvalidInput);
}

// Many views in one call are bit for bit the views captured one at a time,
// each in a call of its own: 48 skeleton_projection views of the
// elephant, face ids on a torus in small non-square views and in large ones
// (what one view leaves in the framebuffer must not reach the next).
TEST(RenderViews, ManyViewsEqualOneViewAtATime) {
  struct Case {
    Mesh mesh;
    int width, height, directions;
    bool face_ids;
  };
  const std::vector<Case> cases = {{read_mesh(test::sample("elephant.off")), 256, 256, 24, false},
                                   {test::torus(), 72, 40, 25, true},
                                   {test::torus(), 1500, 900, 4, true}};
  for (const Case& c : cases) {
    const BBox box = bounding_box(c.mesh);
    std::vector<CameraMatrices> cams;
    for (const Vec3& d : sphere_directions(c.directions)) {
      cams.push_back(orthographic_view(d, box, c.width, c.height));
      cams.push_back(orthographic_view(d * -1.0, box, c.width, c.height));
    }
    const auto many = shared_renderer().capture(c.mesh, cams, {.face_ids = c.face_ids});
    ASSERT_EQ(many.size(), cams.size());
    Renderer alone;
    long seen = 0;
    for (std::size_t v = 0; v < cams.size(); ++v) {
      const auto one = alone.capture(c.mesh, {cams[v]}, {.face_ids = c.face_ids});
      ASSERT_EQ(one.size(), 1u);
      EXPECT_EQ(many[v].camera.view_projection().m, cams[v].view_projection().m) << v;
      ASSERT_EQ(many[v].depth.size(), one[0].depth.size()) << v;
      EXPECT_EQ(std::memcmp(many[v].depth.data(), one[0].depth.data(), one[0].depth.size() * sizeof(float)), 0)
          << "depth of view " << v << " of " << c.width << "x" << c.height;
      EXPECT_EQ(many[v].silhouette, one[0].silhouette) << v;
      EXPECT_EQ(many[v].face_ids, one[0].face_ids) << v;
      EXPECT_EQ(many[v].face_ids.empty(), !c.face_ids);
      for (auto s : one[0].silhouette) seen += s;
    }
    // The views do show the mesh.
    EXPECT_GT(seen, long(cams.size()) * c.width * c.height / 50);
  }
  // And with two contexts, as skeleton_projection draws them; the second
  // context is kept for the next call, which must not see the last one's
  // size, face ids or views.
  for (const Case& c : {cases[0], cases[1], cases[0]}) {
    std::vector<CameraMatrices> cams;
    for (const Vec3& d : sphere_directions(c.directions))
      cams.push_back(orthographic_view(d, bounding_box(c.mesh), c.width, c.height));
    const auto one_context = shared_renderer().capture(c.mesh, cams, {.face_ids = c.face_ids});
    const auto two_contexts = capture_cameras(shared_renderer(), c.mesh, cams, 2, {.face_ids = c.face_ids});
    ASSERT_EQ(one_context.size(), two_contexts.size());
    for (std::size_t v = 0; v < cams.size(); ++v) {
      EXPECT_EQ(one_context[v].depth, two_contexts[v].depth) << v;
      EXPECT_EQ(one_context[v].silhouette, two_contexts[v].silhouette) << v;
      EXPECT_EQ(one_context[v].face_ids, two_contexts[v].face_ids) << v;
    }
  }
}

// One renderer per thread: every thread gets the same picture as one alone.
TEST(RenderResources, RenderersOnSeveralThreads) {
  const Mesh torus = test::torus();
  const Image expected = shared_renderer().render(torus, reference_params()).color;
  std::vector<int> mismatches(4, -1);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t)
    threads.emplace_back([&, t] {
      Renderer r;
      int bad = 0;
      for (int i = 0; i < 10; ++i) bad += r.render(torus, reference_params()).color.rgba != expected.rgba;
      mismatches[t] = bad;
    });
  for (auto& th : threads) th.join();
  for (int m : mismatches) EXPECT_EQ(m, 0);
}

TEST(RenderResources, APoolLendsItsRenderersAndKeepsItsBound) {
  const Mesh torus = test::torus();
  const Image expected = shared_renderer().render(torus, reference_params()).color;
  RendererPool pool(GlPlatform::automatic, 1, 1);
  std::unique_ptr<Renderer> first = pool.take();
  const Renderer* lent = first.get();
  EXPECT_EQ(pool.started(), 1);
  // With one out, a second take waits until it comes back, then gets the same one.
  std::atomic<bool> taken{false};
  const Renderer* second_lent = nullptr;
  std::thread other([&] {
    std::unique_ptr<Renderer> second = pool.take();
    taken = true;
    second_lent = second.get();
    EXPECT_EQ(second->render(torus, reference_params()).color.rgba, expected.rgba);
    pool.give_back(std::move(second));
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_FALSE(taken);
  pool.give_back(std::move(first));
  other.join();
  EXPECT_TRUE(taken);
  EXPECT_EQ(second_lent, lent);
  EXPECT_EQ(pool.started(), 1);
  // A renderer given up (null) frees its place: the next take starts a new one.
  std::unique_ptr<Renderer> r = pool.take();
  pool.give_back(nullptr);
  EXPECT_EQ(pool.started(), 0);
  r = pool.take();
  EXPECT_EQ(pool.started(), 1);
  EXPECT_EQ(r->render(torus, reference_params()).color.rgba, expected.rgba);
  pool.give_back(std::move(r));
  // Beyond max_idle, a renderer given back is destroyed.
  RendererPool open(GlPlatform::automatic, 0, 1);
  std::unique_ptr<Renderer> a = open.take(), b = open.take();
  EXPECT_EQ(open.started(), 2);
  open.give_back(std::move(a));
  open.give_back(std::move(b));
  EXPECT_EQ(open.started(), 1);
}
