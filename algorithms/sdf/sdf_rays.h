// The Shape Diameter Function (Shapira, Shamir and Cohen-Or 2008, "Consistent
// mesh partitioning and skeletonisation using the shape diameter function").
//
// At the centroid c of face f, with inward normal -n, a cone of `rays` rays of
// opening `cone_angle` is cast into the shape.  Ray i leaves along
//   d_i = cos(a/2) (-n) + sin(a/2) R_i (cos Q_i u + sin Q_i v),
// with (R_i, Q_i) Vogel's spiral on the unit disk (R_i = i / rays, the
// sampling CGAL's sdf_values uses) and (u, v) a basis of f's plane.  A ray
// counts when the first face it meets is seen from behind (the ray leaves
// the shape there: dot(d_i, n_hit) > 0); its length is t_i.  Rays whose t_i
// is further than one standard deviation from the median are outliers
// (Shapira et al.; CGAL instead drops those beyond 1.5 median absolute
// deviations), and
//   SDF(f) = sum_i w_i t_i / sum_i w_i,   w_i = 1 / max(angle(d_i, -n), angle_1)
// (the inverse of the ray's angle to the cone's axis; the axis ray gets the
// weight of the next one, so that no weight is infinite).
//
// Ray casting uses Embree (Intel's ray tracing kernels, Debian's libembree):
// a BVH built for the whole mesh once, rays traced on every core; or, where
// the EGL renderer finds a hardware device (SdfParams::device), an OpenGL
// compute shader over a BVH in GPU buffers (rays/gpu_ray_caster.h), which
// tells the faces met from behind as it meets them; the outliers are then
// dropped on the CPU alike (combine_rays).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/mesh.h"
#include "sdf/bilateral_filter.h"
#include "sdf/sdf_params.h"

namespace cgview::sdf {

// The raw SDF of the faces listed (all faces when `faces` is empty): one value
// per listed face, in the mesh's units, NaN where no ray found the inside (a
// degenerate face, or every ray escaped through a hole of an open mesh).
// Only the rays' parameters of `p` count (rays, cone_angle, weights,
// outliers); the rays are cast on every core.  `ctx` (may be null) gets
// progress over [progress_from, progress_to] and is checked for
// cancellation.  Throws InvalidInput for a mesh with no faces, a face not in
// it, parameters outside SdfParams' ranges, or a CGVIEW_SDF_RAYS other than
// auto, cpu or gpu; Error when the GPU path is asked for and cannot start.
struct RawSdf {
  std::vector<double> values;
  std::size_t rays_cast = 0, rays_accepted = 0, missing = 0;
  bool gpu = false;          // the rays ran in the compute shader
  std::string gpu_renderer;  // its GL renderer, when they did
  // When they did: how long the calling thread waited on the shader (the
  // frames' upload, the casts, the hits' download), beside the cores'
  // work on the hits; what is left of the cast's time is the CPU's.
  double gpu_seconds = 0;
};
RawSdf raw_sdf(const Mesh& mesh, const SdfParams& p, std::span<const std::uint32_t> faces = {},
               const Context* ctx = nullptr, double progress_from = 0, double progress_to = 1);

// raw_sdf on every face, and the face graph its post-processing walks
// (postprocess below), built on a thread of its own while the rays are
// cast: where they run on a GPU the cores wait for it meanwhile (the graph
// of the 1.42M-face mesh takes 0.24 s on one core), and on Embree the
// thread takes its share of them.
RawSdf raw_sdf(const Mesh& mesh, const SdfParams& p, Adjacency& face_graph, const Context* ctx, double progress_from,
               double progress_to);

// raw_sdf in rounds on one mesh, its BVH (Embree's, or the GPU's) built
// once: the accelerated SDF casts a second round where its first leaves the
// SDF least certain.  The constructor throws what raw_sdf throws for the
// mesh and `p`, cast() for `faces`; the mesh must outlive the caster.
class SdfRayCaster {
 public:
  SdfRayCaster(const Mesh& mesh, const SdfParams& p);
  ~SdfRayCaster();
  SdfRayCaster(const SdfRayCaster&) = delete;
  SdfRayCaster& operator=(const SdfRayCaster&) = delete;
  RawSdf cast(std::span<const std::uint32_t> faces = {}, const Context* ctx = nullptr, double progress_from = 0,
              double progress_to = 1) const;

 private:
  struct State;
  std::unique_ptr<State> s_;
};

// One face's SDF from its accepted rays' hits, (length, weight) each, at least
// one: the weighted mean of those within the outlier rule's band about
// their median (Outliers::mad: 1.5 median absolute deviations; std_dev:
// one standard deviation; none: all), the median of an even count the mean
// of the two middle lengths as CGAL's; the middle ray's length where the
// band keeps none.  `scratch` is working space.
double combine_rays(std::span<const std::pair<double, double>> hits, Outliers rule, std::vector<double>& scratch);

// CGAL's post-processing of SDF values (Surface_mesh_segmentation's
// Postprocess_sdf_values), with the same rules:
// - fill_missing: the faces in order, a NaN face takes the mean of its edge
//   neighbours' values as they are at its turn (one filled before it
//   counts), else (after all) the smallest value the rays gave;
// - bilateral_smooth (sdf/bilateral_filter.h);
// - normalize: linear to [0, 1] over min..max (all 0.5 when constant).
void fill_missing(const Mesh& mesh, const Adjacency& face_graph, std::vector<double>& values);
std::vector<double> normalize_linear(const std::vector<double>& values);

// What the SDF algorithms do after the rays: holes filled (always: a face
// with no value would break every later step), then the bilateral filter
// when `p.smooth`, over `p.window` rings.
void postprocess(const Mesh& mesh, const Adjacency& face_graph, std::vector<double>& values, const SdfParams& p,
                 const Context& ctx);

// The device rays run on for `p` on this machine (automatic resolved, with
// CGVIEW_SDF_RAYS): gpu where EGL lists a hardware device.
RayDevice ray_device(const SdfParams& p);

// The metrics every SDF algorithm reports of its rays: rays_on_gpu (1 or 0).
void ray_metrics(const RawSdf& raw, Metrics& metrics);

// A warning for the faces whose rays found no inside (open meshes), saying
// what they take instead (`fill`).
void warn_missing(const RawSdf& raw, std::vector<std::string>& warnings,
                  std::string_view fill = "their neighbours' mean, else the smallest value");

// Pearson's correlation of two equally long series (how far two SDFs agree:
// the tests and the benchmark compare ours with CGAL's by it); 0 when either
// is constant or empty.
double pearson(std::span<const double> a, std::span<const double> b);

}  // namespace cgview::sdf
