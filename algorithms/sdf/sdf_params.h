// The SDF parameters shared by sdf, sdf_fast and sdf_segmentation (labels,
// ranges and help live here once), and the steps they share after the rays:
// post-processing and the artifacts they return.
#pragma once

#include <string>
#include <vector>

#include "registry/registry.h"
#include "sdf/sdf.h"

namespace cgview::sdf {

struct SdfParamFields {
  int rays = 25;
  double cone_angle = 120.0;
  std::string weights = "inverse_angle";
  std::string outliers = "std_dev";
  bool smooth = true;
  int window = 0;
  template <class V>
  void describe_sdf(V& v) {
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
  SdfOptions options() const {
    SdfOptions o;
    o.rays = rays;
    o.cone_angle = cone_angle;
    o.weights = weights == "uniform" ? Weights::uniform : Weights::inverse_angle;
    o.outliers = outliers == "mad" ? Outliers::mad : outliers == "none" ? Outliers::none : Outliers::std_dev;
    return o;
  }
};

// Holes filled (always: a face with no value would break every later step),
// then the bilateral filter when `smooth`.
void postprocess(const Mesh& mesh, const Adjacency& face_graph, std::vector<double>& values, const SdfParamFields& p,
                 Context& ctx);

// The per-face field `name` (values in the mesh's units), its normalized copy
// `name`_normalized and its per-vertex average `name`_vertex.
std::vector<Artifact> sdf_fields(const Mesh& mesh, const std::string& name, const std::vector<double>& values);

// Warnings for rays that found no inside (open meshes).
void warn_missing(const RawSdf& raw, std::vector<std::string>& warnings);

// The input of every SDF algorithm: it casts along the inward normal, so a
// closed mesh facing inward is turned outward first (InputSpec::outward).
inline const InputSpec kSdfInput{.name = "mesh",
                                 .kind = OutputKind::mesh,
                                 .help = "the mesh (one whose faces face inward is turned outward)",
                                 .outward = true};

}  // namespace cgview::sdf
