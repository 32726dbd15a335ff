// GpuRayCaster: first hits of rays against a triangle mesh in an OpenGL 4.3
// compute shader, over a BVH in GPU buffers (the CGView paper's "from
// accessing GPU buffers to the visualization of data").  The BVH (median
// splits of the longest axis of the triangles' centroids, leaves of up to 4)
// is built on the CPU, flattened depth-first (a node's left child follows
// it), and uploaded with the triangles into shader storage buffers; one
// shader invocation per ray walks it with a stack, nearest child first, and
// intersects triangles by Moller-Trumbore in float, skipping the face the
// ray leaves from, as RayCaster (rays/ray_caster.h) does on Embree.
//
// It runs on any EGL context with compute shaders: a GPU, or Mesa's llvmpipe
// on the CPU (where Embree is much faster: the SDF chooses it there,
// sdf/sdf_rays.h).  The context is the process's own, one per platform,
// shared by every caster and used by one call at a time.
#pragma once

#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <vector>

#include "core/mesh.h"
#include "rays/ray_caster.h"
#include "render/egl_context.h"

namespace cgview {

class GpuRayCaster {
 public:
  using Hit = RayCaster::Hit;
  static constexpr std::uint32_t kNoFace = RayCaster::kNoFace;
  // A ray as the shader reads it (std430: 32 bytes).  The direction must be
  // of unit length (the distance is along it); a zero direction meets
  // nothing.  Hits are at distances in (0, max_distance).
  struct Ray {
    float origin[3] = {0, 0, 0};
    std::uint32_t skip = kNoFace;  // the face the ray leaves from
    float direction[3] = {0, 0, 0};
    float max_distance = std::numeric_limits<float>::infinity();
  };

  // Builds the BVH and uploads it.  Throws Error when no EGL context starts
  // on `platform`, when it has no compute shaders (OpenGL below 4.3), when
  // the mesh does not fit its storage buffers, or when the shader fails.
  explicit GpuRayCaster(const Mesh& mesh, render::GlPlatform platform = render::GlPlatform::automatic);
  ~GpuRayCaster();
  GpuRayCaster(const GpuRayCaster&) = delete;
  GpuRayCaster& operator=(const GpuRayCaster&) = delete;

  // hits[i]: the first face rays[i] meets (hits is resized).  Rays go to the
  // GPU in batches of about a million.  Thread-safe (calls take turns).
  void first_hits(std::span<const Ray> rays, std::vector<Hit>& hits) const;
  std::vector<Hit> first_hits(std::span<const Ray> rays) const;

  // A cone of rays from a point (std430: 64 bytes): ray k leaves `origin`,
  // skipping `face`, along normalize(-axis_k n + du_k u + dv_k v).  A frame
  // whose face is kNoFace casts nothing (a degenerate face).
  struct Frame {
    float origin[3] = {0, 0, 0};
    std::uint32_t face = kNoFace;
    float n[3] = {0, 0, 0}, pad0 = 0;
    float u[3] = {0, 0, 0}, pad1 = 0;
    float v[3] = {0, 0, 0}, pad2 = 0;
  };
  struct ConeRay {
    float axis = 1, du = 0, dv = 0, pad = 0;
  };
  // A hit as the shader writes it (8 bytes): the face met (kNoFace: none),
  // with the bit kBehind where the ray meets it from behind (along its
  // normal, as a ray from inside a closed mesh leaves it: the SDF's test,
  // which the shader makes from its intersection's determinant, so that
  // the CPU need not remake each ray's direction to make it), and the
  // distance along the ray.
  static constexpr std::uint32_t kBehind = std::uint32_t(1) << 31;
  struct FaceHit {
    float distance;
    std::uint32_t face;
    bool met() const { return face != kNoFace; }
    bool behind() const { return met() && (face & kBehind) != 0; }
    std::uint32_t face_met() const { return met() ? face & ~kBehind : kNoFace; }
  };
  // hits[i * cone.size() + k]: the first face frame i's ray k meets (hits is
  // resized).  The rays are made in the shader, so that an SDF's cones send
  // 64 bytes a face to the GPU instead of 32 a ray; their hits come back as
  // the shader wrote them, read straight into `hits` (a Hit, with its
  // normal, is 40 bytes: on the 1.42M-face mesh, 35.6M of them took the CPU
  // 0.75 s on one thread to fill).
  void cone_hits(std::span<const Frame> frames, std::span<const ConeRay> cone, std::vector<FaceHit>& hits) const;
  // The Hit of a FaceHit: its distance and face, with the face's normal.
  Hit hit(const FaceHit& h) const;

  // Unit normal of each face (zero for a degenerate one), as face_normals():
  // first_hits' hits carry them.
  const std::vector<Vec3>& normals() const;
  // The context's renderer (info().software: llvmpipe and its kin).
  const render::EglInfo& info() const;
  std::size_t bvh_nodes() const { return nodes_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::size_t nodes_ = 0;
};

}  // namespace cgview
