// The GPU ray caster (rays/gpu_ray_caster.h) against Embree's (RayCaster) on
// the same rays: the same first face, at the same distance within float
// rounding.  It runs on whatever EGL context starts: Mesa's llvmpipe where
// there is no GPU.
#include "rays/gpu_ray_caster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/errors.h"
#include "core/threads.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace cgview {
namespace {

using Ray = GpuRayCaster::Ray;

Ray make_ray(const Vec3& o, Vec3 d, std::uint32_t skip = RayCaster::kNoFace) {
  d = normalized(d);
  return {{float(o.x), float(o.y), float(o.z)}, skip, {float(d.x), float(d.y), float(d.z)}};
}
Vec3 origin(const Ray& r) { return {r.origin[0], r.origin[1], r.origin[2]}; }
Vec3 direction(const Ray& r) { return {r.direction[0], r.direction[1], r.direction[2]}; }

// Rays of two kinds, as the SDF and the skeleton measures cast them: from
// each face's centroid into the shape (skipping the face), and from random
// points of the bounding box in random directions.
std::vector<Ray> sample_rays(const Mesh& mesh, std::size_t per_kind) {
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> unit(0, 1);
  const std::vector<Vec3> normals = face_normals(mesh);
  const BBox box = bounding_box(mesh);
  std::vector<Ray> rays;
  for (std::size_t i = 0; i < per_kind; ++i) {
    const std::uint32_t f = std::uint32_t(i * mesh.faces.size() / per_kind);
    const Tri& t = mesh.faces[f];
    const Vec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    const Vec3 jitter{gauss(rng), gauss(rng), gauss(rng)};
    rays.push_back(make_ray(c, -1.0 * normals[f] + 0.5 * normalized(jitter), f));
  }
  for (std::size_t i = 0; i < per_kind; ++i) {
    const Vec3 p = box.min + Vec3{unit(rng) * (box.max.x - box.min.x), unit(rng) * (box.max.y - box.min.y),
                                  unit(rng) * (box.max.z - box.min.z)};
    rays.push_back(make_ray(p, {gauss(rng), gauss(rng), gauss(rng)}));
  }
  return rays;
}

// The GPU's hits of the rays against Embree's: the same face at the same
// distance, but for a ray through an edge or a vertex (either face is right).
void expect_embree_hits(const Mesh& mesh, const std::vector<Ray>& rays, const std::vector<GpuRayCaster::Hit>& hits) {
  const RayCaster cpu(mesh);
  ASSERT_EQ(hits.size(), rays.size());
  const double scale = bounding_box(mesh).diagonal();
  std::size_t hit = 0, same = 0, near_edge = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const RayCaster::Hit e = cpu.first_hit(origin(rays[i]), direction(rays[i]), rays[i].skip);
    const GpuRayCaster::Hit g = hits[i];
    hit += bool(e);
    if (bool(e) == bool(g) && e.face == g.face) {
      ++same;
      if (e) {
        EXPECT_NEAR(g.distance, e.distance, 1e-5 * scale) << "ray " << i;
        EXPECT_GT(dot(normalized(g.normal), normalized(e.normal)), 1 - 1e-5) << "ray " << i;
      }
    } else if (e && g && std::abs(e.distance - g.distance) < 1e-5 * scale) {
      ++near_edge;
    } else {
      ADD_FAILURE() << "ray " << i << ": Embree face " << e.face << " at " << e.distance << ", GPU face " << g.face
                    << " at " << g.distance;
    }
  }
  EXPECT_GT(hit, rays.size() / 2);  // the comparison is about hits, mostly
  EXPECT_GE(same, rays.size() - rays.size() / 1000) << near_edge << " hits through edges";
}

TEST(GpuRayCaster, SameHitsAsEmbreeOnASampleMesh) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const GpuRayCaster gpu(mesh);
  const std::vector<Ray> rays = sample_rays(mesh, 4000);
  expect_embree_hits(mesh, rays, gpu.first_hits(rays));
  RecordProperty("renderer", gpu.info().gl_renderer);
}

// Above 64k faces the BVH's top levels are built on threads of their own
// (on a machine of two cores or more): the same hits.
TEST(GpuRayCaster, SameHitsAsEmbreeOnAMeshLargeEnoughToBuildOnThreads) {
  const Mesh mesh = read_mesh(test::sample("refined_elephant.off"));
  ASSERT_GT(mesh.faces.size(), kItemsPerThread);
  const GpuRayCaster gpu(mesh);
  const std::vector<Ray> rays = sample_rays(mesh, 2000);
  expect_embree_hits(mesh, rays, gpu.first_hits(rays));
}

TEST(GpuRayCaster, ConesMadeInTheShaderHitAsTheSameRaysFromTheCpu) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const GpuRayCaster gpu(mesh);
  const std::vector<Vec3> normals = face_normals(mesh);
  // A cone of 9 rays around the inward normal, and 3 around the outward
  // one (which meet other parts of the shape from their front), every 7th
  // face.
  std::vector<GpuRayCaster::ConeRay> cone;
  for (int k = 0; k < 12; ++k)
    cone.push_back({k < 9 ? 0.8f : -0.8f, 0.6f * float(std::cos(k)), 0.6f * float(std::sin(k)) * k / 12});
  std::vector<GpuRayCaster::Frame> frames;
  std::vector<Ray> rays;
  const auto f3 = [](const Vec3& a, float* out) { out[0] = float(a.x), out[1] = float(a.y), out[2] = float(a.z); };
  for (std::uint32_t f = 0; f < mesh.faces.size(); f += 7) {
    const Tri& t = mesh.faces[f];
    const Vec3 c = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) / 3.0;
    const Vec3 u = normalized(mesh.positions[t[1]] - mesh.positions[t[0]]), v = cross(normals[f], u);
    GpuRayCaster::Frame fr;
    fr.face = f;
    f3(c, fr.origin), f3(normals[f], fr.n), f3(u, fr.u), f3(v, fr.v);
    frames.push_back(fr);
    for (const auto& k : cone)
      rays.push_back(make_ray({fr.origin[0], fr.origin[1], fr.origin[2]},
                              -double(k.axis) * normals[f] + double(k.du) * u + double(k.dv) * v, f));
  }
  frames.push_back({});  // a degenerate face's: no rays
  std::vector<GpuRayCaster::FaceHit> found;
  gpu.cone_hits(frames, cone, found);
  ASSERT_EQ(found.size(), frames.size() * cone.size());
  std::vector<GpuRayCaster::Hit> hits;
  for (const GpuRayCaster::FaceHit& h : found) hits.push_back(gpu.hit(h));
  for (std::size_t k = 0; k < cone.size(); ++k) EXPECT_FALSE(hits[hits.size() - 1 - k]);
  hits.resize(rays.size());
  expect_embree_hits(mesh, rays, hits);
  // The side each face is met from, against its normal on the CPU (a
  // grazing ray's is float's call).
  std::size_t behind = 0, front = 0;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!found[i].met()) continue;
    const Vec3 d{rays[i].direction[0], rays[i].direction[1], rays[i].direction[2]};
    const double side = dot(d, normals[found[i].face_met()]);
    if (std::abs(side) < 1e-4) continue;
    EXPECT_EQ(found[i].behind(), side > 0) << i;
    ++(side > 0 ? behind : front);
  }
  EXPECT_GT(behind, 1000u);
  EXPECT_GT(front, 10u);
}

TEST(GpuRayCaster, SkipsTheOriginFaceAndHonoursTheMaximumDistance) {
  const Mesh cube = test::box();  // [0, 1]^3
  const GpuRayCaster gpu(cube);
  const RayCaster cpu(cube);  // the same answers, where a face is skipped
  // Along +x (off the side's diagonal): the face at x = 1, at distance 0.5.
  const Vec3 o{0.5, 0.2, 0.7};
  Ray r = make_ray(o, {1, 0, 0});
  GpuRayCaster::Hit h = gpu.first_hits({&r, 1})[0];
  ASSERT_TRUE(h);
  EXPECT_NEAR(h.distance, 0.5, 1e-6);
  EXPECT_NEAR(cube.positions[cube.faces[h.face][0]].x, 1.0, 1e-12);
  // Skipping that face, the ray leaves the box: nothing else lies ahead.
  r.skip = h.face;
  EXPECT_FALSE(gpu.first_hits({&r, 1})[0]);
  EXPECT_FALSE(cpu.first_hit(o, {1, 0, 0}, h.face));
  // Short of the face: nothing.
  r = make_ray(o, {1, 0, 0});
  r.max_distance = 0.4f;
  EXPECT_FALSE(gpu.first_hits({&r, 1})[0]);
  // A zero direction meets nothing; a ray past the box, nothing.
  const Ray rays[] = {Ray{{0.5f, 0.5f, 0.5f}}, make_ray({2, 2, 2}, {1, 1, 1})};
  for (const GpuRayCaster::Hit& g : gpu.first_hits(rays)) EXPECT_FALSE(g);
  // Several batches' worth of rays in one call give the same hits.
  std::vector<Ray> many((1u << 20) + 1000, make_ray(o, {0, 0, -1}));
  const std::vector<GpuRayCaster::Hit> all = gpu.first_hits(many);
  for (std::size_t i = 0; i < all.size(); i += 4099) ASSERT_NEAR(all[i].distance, 0.7, 1e-6) << i;
  EXPECT_NEAR(all.back().distance, 0.7, 1e-6);
  // And as cones (3 rays a frame: down, up, and +x): several batches too.
  GpuRayCaster::Frame down;
  for (int j = 0; j < 3; ++j) down.origin[j] = float(o[j]);
  down.n[2] = 1, down.u[0] = 1, down.v[1] = 1;   // the axis is -n
  down.face = std::uint32_t(cube.faces.size());  // no face of the cube's to skip
  const GpuRayCaster::ConeRay cone[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
  std::vector<GpuRayCaster::FaceHit> hits;
  gpu.cone_hits(std::vector<GpuRayCaster::Frame>(700000, down), cone, hits);
  ASSERT_EQ(hits.size(), 2100000u);
  for (std::size_t i = 0; i < hits.size(); i += 3001) {
    const double expected[] = {0.7, 0.3, 0.5};
    ASSERT_NEAR(hits[i].distance, expected[i % 3], 1e-6) << i;
    // From inside, each face is met from behind (the box's normals face out).
    ASSERT_TRUE(hits[i].behind()) << i;
  }
  // From above the box, down meets the top from its front; up and +x, nothing.
  GpuRayCaster::Frame above = down;
  above.origin[2] = 2;
  gpu.cone_hits({&above, 1}, cone, hits);
  ASSERT_EQ(hits.size(), 3u);
  EXPECT_TRUE(hits[0].met());
  EXPECT_FALSE(hits[0].behind());
  EXPECT_NEAR(hits[0].distance, 1.0, 1e-6);
  EXPECT_NEAR(cube.positions[cube.faces[hits[0].face_met()][0]].z, 1.0, 1e-12);
  EXPECT_FALSE(hits[1].met() || hits[2].met());
}

TEST(GpuRayCaster, EmptyMeshIsInvalidInput) { EXPECT_THROW(GpuRayCaster(Mesh{}), InvalidInput); }

}  // namespace
}  // namespace cgview
