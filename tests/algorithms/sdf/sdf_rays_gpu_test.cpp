// The SDF's rays in the compute shader (SdfParams::device, CGVIEW_SDF_RAYS)
// against the same SDF on Embree: the same values, and the path that ran in
// the job's metrics.  The GPU path runs on Mesa's llvmpipe where there is no
// GPU.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <vector>

#include "core/errors.h"
#include "io/mesh_io.h"
#include "render/egl_context.h"
#include "sdf/sdf.h"
#include "sdf/sdf_rays.h"
#include "test_support.h"

namespace cgview::sdf {
namespace {

TEST(SdfRaysGpu, SameValuesAsEmbree) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  const SdfResult cpu = sdf(mesh, {.device = RayDevice::cpu});
  const SdfResult gpu = sdf(mesh, {.device = RayDevice::gpu});
  EXPECT_EQ(cpu.metrics.at("rays_on_gpu"), 0.0);
  EXPECT_EQ(gpu.metrics.at("rays_on_gpu"), 1.0);
  EXPECT_EQ(gpu.metrics.at("rays_cast"), cpu.metrics.at("rays_cast"));
  // A ray through an edge may take the other face: a few rays of ~139k.
  EXPECT_NEAR(gpu.metrics.at("rays_accepted"), cpu.metrics.at("rays_accepted"), 20);
  const auto& a = cpu.sdf.values;
  const auto& b = gpu.sdf.values;
  ASSERT_EQ(a.size(), b.size());
  const double range = cpu.metrics.at("max") - cpu.metrics.at("min");
  std::size_t close = 0;
  for (std::size_t f = 0; f < a.size(); ++f) close += std::abs(a[f] - b[f]) <= 1e-4 * range;
  EXPECT_GE(close, a.size() - a.size() / 500);
  EXPECT_GT(pearson(std::vector<double>(a.begin(), a.end()), std::vector<double>(b.begin(), b.end())), 0.99999);
}

// The GPU casts a million rays at a time while the cores take the last
// million's hits and make the next million's cones: 1024 rays on 2100 faces
// go in three such chunks, the first two buffers' used twice.
TEST(SdfRaysGpu, RaysInSeveralChunksGiveEmbreesValues) {
  const Mesh mesh = read_mesh(test::sample("elephant.off"));
  std::vector<std::uint32_t> faces(2100);
  for (std::size_t i = 0; i < faces.size(); ++i) faces[i] = std::uint32_t(i * 2);
  const RawSdf cpu = raw_sdf(mesh, {.rays = kMaxRays, .device = RayDevice::cpu}, faces);
  const RawSdf gpu = raw_sdf(mesh, {.rays = kMaxRays, .device = RayDevice::gpu}, faces);
  ASSERT_TRUE(gpu.gpu);
  ASSERT_GT(gpu.rays_cast, std::size_t(2) << 20);
  EXPECT_GT(gpu.gpu_seconds, 0.0);  // the wait on the shader, measured
  EXPECT_EQ(cpu.gpu_seconds, 0.0);
  EXPECT_NEAR(double(gpu.rays_accepted), double(cpu.rays_accepted), 1e-4 * double(cpu.rays_accepted));
  ASSERT_EQ(gpu.values.size(), faces.size());
  const auto [lo, hi] = std::minmax_element(cpu.values.begin(), cpu.values.end());
  std::size_t close = 0;
  for (std::size_t i = 0; i < faces.size(); ++i) close += std::abs(cpu.values[i] - gpu.values[i]) <= 1e-4 * (*hi - *lo);
  EXPECT_GE(close, faces.size() - faces.size() / 500);
}

TEST(SdfRaysGpu, EnvironmentChoosesAndAutomaticFollowsTheRenderer) {
  // Automatic: the GPU where EGL lists a hardware device (llvmpipe: Embree).
  EXPECT_EQ(ray_device({}) == RayDevice::gpu, render::hardware_device_listed());
  const Mesh cube = test::box();
  ::setenv("CGVIEW_SDF_RAYS", "gpu", 1);
  EXPECT_EQ(ray_device({}), RayDevice::gpu);
  EXPECT_TRUE(raw_sdf(cube, {}).gpu);
  EXPECT_FALSE(raw_sdf(cube, {.device = RayDevice::cpu}).gpu);  // the parameter wins
  ::setenv("CGVIEW_SDF_RAYS", "cpu", 1);
  EXPECT_FALSE(raw_sdf(cube, {}).gpu);
  ::setenv("CGVIEW_SDF_RAYS", "tpu", 1);
  try {
    raw_sdf(cube, {});
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("CGVIEW_SDF_RAYS"), std::string::npos) << e.what();
  }
  ::unsetenv("CGVIEW_SDF_RAYS");
}

}  // namespace
}  // namespace cgview::sdf
