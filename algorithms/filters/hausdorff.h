// hausdorff: the distance between two meshes, with a per-vertex error field.
//
// The symmetric Hausdorff distance max(h(A,B), h(B,A)), h(A,B) = max over
// points a of A of min over points b of B of |a - b|, by CGAL's
// bounded_error_Hausdorff_distance (Krayer and Müller 2021): exact within
// `error_bound` times the bounding-box diagonal, over the whole surfaces, not
// only at vertices.  The field is the distance from each vertex of "mesh" to
// the surface of "reference" (closest point on an AABB tree of its
// triangles), for the colour map; its maximum is a lower bound of h(A,B).
//
//   Mesh a = read_mesh("bunny.off"), b = read_mesh("bunny_simplified.off");
//   HausdorffResult r = hausdorff(a, b, {.error_bound = 1e-5});
//   double d = r.metrics.at("hausdorff");  // r.distance: per vertex of a
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/scalar_field.h"
#include "filters/repair_param.h"
#include "registry/registry.h"

namespace cgview {

struct HausdorffParams {
  double error_bound = 1e-4;
  bool repair = true;  // describe_repair (filters/repair_param.h): both meshes
  template <class V>
  void describe(V& v) {
    v.number("error_bound", error_bound,
             {.label = "Error bound",
              .min = 1e-7,
              .max = 0.1,
              .help = "how far from the exact Hausdorff distance the answer may be, as a fraction of the "
                      "bounding-box diagonal of both meshes"});
    describe_repair(v, repair);
  }
};

struct HausdorffResult {
  ScalarField distance;  // per vertex of `mesh`: its distance to `reference`
  // hausdorff, mesh_to_reference, reference_to_mesh, hausdorff_relative,
  // error_bound (absolute), bbox_diagonal, vertex_distance_{max,mean,rms}
  Metrics metrics;
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("distance", distance);
    v("metrics", metrics);
  }
};

// Either mesh, when not manifold, is measured as a repaired copy (`repair`,
// on by default: a warning names the input and says what changed; the
// repair moves no point, and the field stays one value per vertex of
// `mesh`).  Throws InvalidInput when either mesh has no faces, or is not
// manifold with `repair` off.
HausdorffResult hausdorff(const Mesh& mesh, const Mesh& reference, const HausdorffParams& p = {},
                          Context* ctx = nullptr);

}  // namespace cgview
