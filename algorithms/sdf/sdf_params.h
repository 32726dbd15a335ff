// The parameters of the Shape Diameter Function, described once: SdfParams
// is the sdf algorithm's (sdf/sdf.h), and sdf_fast and sdf_segmentation hold
// one as their `.sdf`, so that the rays, the cone, the weights, the outlier
// rule and the smoothing have one label, range and default everywhere.
// raw_sdf (sdf/sdf_rays.h) takes them too.
//
//   sdf::sdf(mesh, {.cone_angle = 90, .outliers = sdf::Outliers::mad});
//   sdf::sdf_fast(mesh, {.fraction = 0.2, .sdf = {.rays = 50}});
#pragma once

#include "registry/registry.h"

namespace cgview::sdf {

// inverse_angle: each length weighted by the inverse of its angle to the
// cone's axis (Shapira et al.); uniform: all alike (CGAL's sdf_values).
enum class Weights { inverse_angle, uniform };
// std_dev: lengths further than one standard deviation from the median are
// dropped (Shapira et al.); mad: further than 1.5 median absolute deviations
// (CGAL); none: all kept.
enum class Outliers { std_dev, mad, none };

inline constexpr int kMaxRays = 1024;

// Where the rays are cast: automatic (an OpenGL compute shader where the EGL
// renderer finds a hardware device, else Embree on the CPU; the environment
// variable CGVIEW_SDF_RAYS=auto|cpu|gpu overrides it), cpu (Embree) or gpu
// (the compute shader on whatever context starts, llvmpipe included).
enum class RayDevice { automatic, cpu, gpu };

struct SdfParams {
  int rays = 25;
  double cone_angle = 120.0;  // degrees
  Weights weights = Weights::inverse_angle;
  Outliers outliers = Outliers::std_dev;
  bool smooth = true;
  int window = 0;
  // Not a parameter of the algorithms' forms: a choice of the machine (as
  // the renderer's platform is), for tests and benchmarks.
  RayDevice device = RayDevice::automatic;
  template <class V>
  void describe(V& v) {
    v.integer("rays", rays, {.label = "Rays", .min = 1, .max = kMaxRays, .help = "rays in each face's cone"});
    v.number("cone_angle", cone_angle,
             {.label = "Cone angle (degrees)",
              .min = 1,
              .max = 179,
              .help = "the cone's full opening around the inward normal"});
    v.choice(
        "weights", weights,
        {.label = "Ray weights",
         .help = "inverse_angle: each length weighted by the inverse of its angle to the cone's axis (Shapira et al.); "
                 "uniform: all rays alike (CGAL's sdf_values)",
         .choices = {"inverse_angle", "uniform"},
         .advanced = true});
    v.choice("outliers", outliers,
             {.label = "Outliers",
              .help = "std_dev: drop lengths further than one standard deviation from the median (Shapira et al.); "
                      "mad: further than 1.5 median absolute deviations (CGAL); none: keep all",
              .choices = {"std_dev", "mad", "none"},
              .advanced = true});
    v.boolean(
        "smooth", smooth,
        {.label = "Bilateral smoothing",
         .help = "CGAL's post-processing: holes filled from neighbours, then a bilateral filter over edge-rings"});
    v.integer("window", window,
              {.label = "Smoothing window (rings)",
               .min = 0,
               .max = 64,
               .help = "0: floor(sqrt(faces / 2000)) + 1, as CGAL",
               .advanced = true,
               .when = {"smooth", {"true"}}});
  }
};

// The input of every SDF algorithm: it casts along the inward normal, so a
// closed mesh facing inward is turned outward first (InputSpec::outward).
inline const InputSpec kSdfInput{.name = "mesh",
                                 .kind = OutputKind::mesh,
                                 .help = "the mesh (one whose faces face inward is turned outward)",
                                 .outward = true};

}  // namespace cgview::sdf
