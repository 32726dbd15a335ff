// RayCaster: first hits of rays against a triangle mesh, on Embree (Intel's
// ray tracing kernels, Debian's libembree): a BVH built once, then queries
// from any number of threads.  Shared by the SDF (sdf/) and the skeleton
// metrics (skeleton/); Embree's headers stay in ray_caster.cpp.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <vector>

#include "core/mesh.h"

namespace cgview {

class RayCaster {
 public:
  static constexpr std::uint32_t kNoFace = std::numeric_limits<std::uint32_t>::max();
  struct Hit {
    double distance = 0;           // along the unit direction
    std::uint32_t face = kNoFace;  // kNoFace: the ray met nothing
    // The face's normal, not necessarily of unit length: which side the
    // ray met the face from.  Embree's geometric normal, (b - a) x (c - a),
    // computed by the intersection: reading the face's normal from memory
    // instead was a cache miss on a large mesh (9% of sdf_fast's time on a
    // 75k-face mesh).  GpuRayCaster's hits carry the face's unit normal.
    Vec3 normal;
    explicit operator bool() const { return face != kNoFace; }
  };

  // Builds the BVH of the mesh (vertices as floats).  Throws Error when
  // Embree cannot start or allocate.
  explicit RayCaster(const Mesh& mesh);
  ~RayCaster();
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // The first face met from `origin` along `direction` (any length), never
  // `skip` (the face a ray leaves from), within max_distance.  Thread-safe.
  Hit first_hit(const Vec3& origin, const Vec3& direction, std::uint32_t skip = kNoFace,
                double max_distance = std::numeric_limits<double>::infinity()) const;
  // Unit normal of each face (zero for a degenerate one), as face_normals().
  const std::vector<Vec3>& normals() const { return normals_; }
  // Whether p is inside a closed, consistently oriented mesh: along a
  // majority of three fixed directions the first face met is seen from
  // behind (from in front where the faces face in, as the first faces met
  // from outside the bounding box tell).
  bool inside(const Vec3& p) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<Vec3> normals_;
  bool faces_out_ = true;  // the faces face out
};

}  // namespace cgview
