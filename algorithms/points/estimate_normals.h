// estimate_normals: a normal at each point of a cloud, from its k nearest
// neighbours, then (optionally) given one consistent side.
//
// jet: the normal of a quadric (a degree-2 jet, the osculating jet of Cazals
// and Pouget, "Estimating differential quantities using polynomial fitting of
// osculating jets", SGP 2003) fitted to the k neighbours by least squares:
// CGAL's jet_estimate_normals.  pca: the direction of least variance of the
// k neighbours, the eigenvector of the smallest eigenvalue of their
// covariance matrix (Hoppe et al., "Surface reconstruction from unorganized
// points", SIGGRAPH 1992): CGAL's pca_estimate_normals.  Either gives a line,
// not a side: with `orient`, the sign is propagated along a minimum spanning
// tree of the k-nearest-neighbour graph weighted by 1 - |n_i . n_j| (Hoppe
// et al. 1992), from the highest point (largest z), whose normal is made to
// point up: CGAL's mst_orient_normals.  On a closed surface sampled densely
// enough, the normals then point outward.
//
// Output: the cloud with one unit normal per point, positions and colours
// as they were (normals it had are replaced).  Points the tree could not
// reach keep the sign the fit gave them; a warning says how many.
//
//   PointCloud c = points_of(read_mesh("scan.ply"));
//   EstimateNormalsResult r = estimate_normals(c, {.method = NormalMethod::pca, .neighbors = 24});
//   write_mesh(as_mesh(r.points), "scan_normals.ply");
#pragma once

#include <string>
#include <vector>

#include "core/point_cloud.h"
#include "registry/registry.h"

namespace cgview {

enum class NormalMethod { jet, pca };

struct EstimateNormalsParams {
  NormalMethod method = NormalMethod::jet;
  int neighbors = 18;
  bool orient = true;
  template <class V>
  void describe(V& v) {
    v.choice("method", method,
             {.label = "Method",
              .help = "jet: fit a quadric to the neighbours (smoother on curved surfaces); pca: the plane of least "
                      "variance of the neighbours (faster)",
              .choices = {"jet", "pca"}});
    v.integer("neighbors", neighbors,
              {.label = "Neighbours",
               .min = 3,
               .max = 500,
               .help = "how many nearest points each normal is fitted to (and the orientation's graph joins)"});
    v.boolean("orient", orient,
              {.label = "Orient",
               .help = "give the normals one consistent side (outward on a closed surface) along a minimum spanning "
                       "tree of the neighbours"});
  }
};

struct EstimateNormalsResult {
  PointCloud points;  // the input's positions and colours, one unit normal per point
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("points", points);
  }
};

// Throws InvalidInput for a parameter outside its range (check_params), an
// invalid cloud (PointCloud::validate), and a cloud of fewer points than a
// fit needs (3 for pca, 6 for jet).  Points whose neighbours give no normal
// (all coincide or lie on a line) get a zero normal and a warning.
// ctx (optional): progress and cancellation (throws Cancelled).
EstimateNormalsResult estimate_normals(const PointCloud& cloud, const EstimateNormalsParams& p = {},
                                       Context* ctx = nullptr);

}  // namespace cgview
