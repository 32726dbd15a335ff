// poisson_reconstruction: a closed surface through a cloud of points with
// normals, the zero level set of the indicator function whose gradient best
// matches the normals (Kazhdan, Bolitho and Hoppe, "Poisson surface
// reconstruction", SGP 2006), as CGAL builds it: the Poisson equation
// Laplacian(f) = div(N) solved on a refined 3D Delaunay triangulation of the
// points (Eigen's sparse solver), then f = 0 meshed by Delaunay refinement
// (Boissonnat and Oudot 2005) inside a sphere of 5 times the cloud's
// bounding sphere: CGAL's Poisson_reconstruction_function and
// make_surface_mesh, the steps of poisson_surface_reconstruction_delaunay.
//
// The mesh's triangles have angles of at least `angle` degrees, Delaunay
// balls of radius at most `radius` average spacings and centres within
// `distance` average spacings of the surface; the average spacing is the
// mean distance from a point to its 6 nearest neighbours
// (compute_average_spacing).  The faces point outward (positive volume).
// Two runs on the same cloud may give different triangles of the same
// accuracy: the mesher starts from random points on the surface (seeding
// CGAL's default generator for it was tried: runs still differed).
//
// A cloud without normals gets them first from estimate_normals (jet, 18
// neighbours, oriented), and a warning says so: normals pointing inward
// turn the surface inside out, so a cloud whose normals are known should
// bring them.
//
//   PointCloud c = points_of(read_mesh("scan_normals.ply"));
//   PoissonReconstructionResult r = poisson_reconstruction(c);
//   write_mesh(r.mesh, "scan_surface.ply");
#pragma once

#include <string>
#include <vector>

#include "core/mesh.h"
#include "core/point_cloud.h"
#include "registry/registry.h"

namespace cgview {

struct PoissonReconstructionParams {
  double angle = 20.0;
  double radius = 30.0;
  double distance = 0.375;
  template <class V>
  void describe(V& v) {
    v.number("angle", angle,
             {.label = "Smallest angle",
              .min = 1,
              .max = 30,
              .help = "each triangle's smallest angle, in degrees, at least this (the mesher ends for 30 or less)"});
    v.number("radius", radius,
             {.label = "Triangle size",
              .min = 0.1,
              .max = 1000,
              .help = "the largest radius of a triangle's Delaunay ball, in average point spacings"});
    v.number("distance", distance,
             {.label = "Approximation error",
              .min = 0.01,
              .max = 100,
              .help = "how far a triangle's centre may be from the implicit surface, in average point spacings"});
  }
};

struct PoissonReconstructionResult {
  Mesh mesh;  // triangles, outward
  std::vector<std::string> warnings;
  template <class V>
  void outputs(V& v) {
    v("mesh", mesh);
  }
};

// Throws InvalidInput for a parameter outside its range (check_params), an
// invalid cloud (PointCloud::validate), fewer than 6 points, and a cloud
// the solver or the mesher finds no surface for (coplanar points, normals
// that cancel out).  A warning when the normals were estimated, and when
// the mesh is not closed.  ctx (optional): progress between the steps, and
// cancellation between them (throws Cancelled).
PoissonReconstructionResult poisson_reconstruction(const PointCloud& cloud, const PoissonReconstructionParams& p = {},
                                                   Context* ctx = nullptr);

}  // namespace cgview
