#include "rays/gpu_ray_caster.h"

#include <algorithm>
#include <cstddef>
#include <cmath>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "core/errors.h"
#include "core/threads.h"
#include "render/gl_functions.h"

namespace cgview {
namespace {

using render::EglContext;
using render::GlComputeFunctions;
using render::GlFunctions;
using render::GlPlatform;

// The shader's buffers, std430.  A node's children: the next node and node
// `a`; a leaf (count > 0) holds triangles a .. a + count - 1.
struct GpuNode {
  float lo[3];
  std::uint32_t a;
  float hi[3];
  std::uint32_t count;
};
struct GpuTri {  // v0, and the edges v1 - v0, v2 - v0
  float v0[3];
  std::uint32_t face;
  float e1[3];
  float pad1;
  float e2[3];
  float pad2;
};
using GpuHit = GpuRayCaster::FaceHit;
static_assert(sizeof(GpuNode) == 32 && sizeof(GpuTri) == 48 && sizeof(GpuHit) == 8);
static_assert(sizeof(GpuRayCaster::Ray) == 32 && sizeof(GpuRayCaster::Frame) == 64 &&
              sizeof(GpuRayCaster::ConeRay) == 16);

// The shader writes these as literals.
static_assert(GpuRayCaster::kNoFace == 0xFFFFFFFFu && GpuRayCaster::kBehind == 0x80000000u);

constexpr int kLeafSize = 4;
constexpr std::size_t kBatch = std::size_t(1) << 20;
constexpr int kGroupSize = 64;

const char* kShader = R"(#version 430
layout(local_size_x = 64) in;
struct Node { vec3 lo; uint a; vec3 hi; uint count; };
struct Tri { vec3 v0; uint face; vec3 e1; float pad1; vec3 e2; float pad2; };
struct Ray { vec3 origin; uint skip; vec3 direction; float max_distance; };
struct Hit { float distance; uint face; };
struct Frame { vec3 origin; uint face; vec3 n; float pad0; vec3 u; float pad1; vec3 v; float pad2; };
layout(std430, binding = 0) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 1) readonly buffer Tris { Tri tris[]; };
layout(std430, binding = 2) readonly buffer Rays { Ray rays[]; };
layout(std430, binding = 3) writeonly buffer Hits { Hit hits[]; };
layout(std430, binding = 4) readonly buffer Frames { Frame frames[]; };
layout(std430, binding = 5) readonly buffer Cone { vec4 cone[]; };
uniform uint ray_count;
uniform uint cone_rays;  // 0: the rays are `rays`; else each frame's cone of this many

Ray ray(uint i) {
  if (cone_rays == 0u) return rays[i];
  Frame f = frames[i / cone_rays];
  vec4 k = cone[i % cone_rays];
  Ray r;
  r.origin = f.origin;
  r.skip = f.face;
  r.direction = f.face == 0xFFFFFFFFu ? vec3(0.0) : normalize(-k.x * f.n + k.y * f.u + k.z * f.v);
  r.max_distance = uintBitsToFloat(0x7F800000u);  // infinity
  return r;
}

// Where the ray enters the box within (0, best), else a huge value.
float enter(vec3 lo, vec3 hi, vec3 o, vec3 inv, float best) {
  vec3 a = (lo - o) * inv, b = (hi - o) * inv;
  vec3 near = min(a, b), far = max(a, b);
  float t0 = max(max(near.x, near.y), max(near.z, 0.0));
  float t1 = min(min(far.x, far.y), min(far.z, best));
  return t0 <= t1 ? t0 : 3.0e38;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= ray_count) return;
  Ray r = ray(i);
  float best = r.max_distance;
  uint face = 0xFFFFFFFFu;
  if (dot(r.direction, r.direction) > 0.0) {
    // Zero components: a huge inverse of their sign, not an infinity (0 * inf is NaN).
    vec3 inv = vec3(r.direction.x < 0.0 ? -1.0 : 1.0, r.direction.y < 0.0 ? -1.0 : 1.0,
                    r.direction.z < 0.0 ? -1.0 : 1.0) / max(abs(r.direction), vec3(1.0e-30));
    // Median splits: depth at most log2(faces), and one node pushed a level.
    uint stack[32];
    int top = 0;
    uint node = 0u;
    if (enter(nodes[0].lo, nodes[0].hi, r.origin, inv, best) < 3.0e38) {
      for (;;) {
        Node n = nodes[node];
        if (n.count > 0u) {
          for (uint k = n.a; k < n.a + n.count; ++k) {
            Tri t = tris[k];
            if (t.face == r.skip) continue;
            vec3 p = cross(r.direction, t.e2);
            float det = dot(t.e1, p);
            if (det == 0.0) continue;
            float f = 1.0 / det;
            vec3 s = r.origin - t.v0;
            float u = f * dot(s, p);
            if (u < 0.0 || u > 1.0) continue;
            vec3 q = cross(s, t.e1);
            float v = f * dot(r.direction, q);
            if (v < 0.0 || u + v > 1.0) continue;
            float d = f * dot(t.e2, q);
            if (d > 0.0 && d < best) {
              best = d;
              // det = -dot(direction, e1 x e2): negative where the ray
              // goes along the face's normal (from behind).
              face = det < 0.0 ? t.face | 0x80000000u : t.face;
            }
          }
        } else {
          uint l = node + 1u, h = n.a;
          float tl = enter(nodes[l].lo, nodes[l].hi, r.origin, inv, best);
          float th = enter(nodes[h].lo, nodes[h].hi, r.origin, inv, best);
          if (tl < 3.0e38 && th < 3.0e38) {
            if (th < tl) { uint x = l; l = h; h = x; }
            stack[top++] = h;
            node = l;
            continue;
          }
          if (tl < 3.0e38) { node = l; continue; }
          if (th < 3.0e38) { node = h; continue; }
        }
        if (top == 0) break;
        node = stack[--top];
      }
    }
  }
  hits[i] = Hit(best, face);
}
)";

// The process's context for a platform and its compiled program, never
// destroyed (at exit the EGL library may be gone before static destructors
// run, as the renderer pool's).
struct SharedContext {
  std::mutex mutex;
  std::unique_ptr<EglContext> context;
  GLuint program = 0;
  GLint ray_count = -1, cone_rays = -1;
};

SharedContext& shared_context(GlPlatform platform) {
  static auto* contexts = new SharedContext[3];
  return contexts[int(platform)];
}

// Holds the shared context current on this thread, with its lock.
class Current {
 public:
  explicit Current(SharedContext& s) : lock_(s.mutex), s_(s) {
    s.context->make_current();
    for (int k = 0; k < 16 && gl().glGetError() != GL_NO_ERROR; ++k) {  // errors left by an earlier call
    }
  }
  ~Current() { s_.context->release(); }
  const GlFunctions& gl() const { return s_.context->gl(); }
  const GlComputeFunctions& gc() const { return *s_.context->gl_compute(); }
  void check(const char* what) const {
    if (const GLenum e = gl().glGetError(); e != GL_NO_ERROR)
      throw Error(std::string("GPU rays: ") + what + " failed (GL error " + std::to_string(e) +
                  (e == GL_OUT_OF_MEMORY ? ", out of GPU memory)" : ")"));
  }

 private:
  std::lock_guard<std::mutex> lock_;
  SharedContext& s_;
};

// The flattened BVH: nodes depth-first, triangles in leaf order.  Median
// splits along the centroids' longest extent, into leaves of at most
// kLeafSize triangles (a node's left child follows it).  The faces'
// centroids travel with their numbers, 16 bytes an item, so that each
// level's splits stream through memory; a node's box is its children's,
// made on the way back up, and the faces' own boxes are read once, at the
// leaves.  (Items by number into the mesh's centroids and a box from every
// triangle at every level took 0.29 s on the 1.42M-face mesh, 2 cores;
// this 0.16 s.)
class BvhBuilder {
 public:
  explicit BvhBuilder(const Mesh& mesh) : mesh_(mesh), items_(mesh.faces.size()), boxes_(mesh.faces.size()) {
    const std::size_t n = mesh.faces.size();
    // Boxes a little larger than their triangles, so that float rounding in
    // the slab test never loses a hit on a box's face.
    const double pad = 1e-6 * bounding_box(mesh).diagonal() + 1e-30;
    on_shares(n, threads_for(n, kItemsPerThread), [&](std::size_t b, std::size_t e) {
      for (std::size_t f = b; f < e; ++f) {
        const Tri& t = mesh.faces[f];
        const Vec3 p = mesh.positions[t[0]], q = mesh.positions[t[1]], r = mesh.positions[t[2]];
        const Vec3 c = face_centroid(mesh, f);
        items_[f] = {{float(c.x), float(c.y), float(c.z)}, std::uint32_t(f)};
        for (int j = 0; j < 3; ++j) {
          boxes_[f].lo[j] = float(std::min({p[j], q[j], r[j]}) - pad);
          boxes_[f].hi[j] = float(std::max({p[j], q[j], r[j]}) + pad);
        }
      }
    });
    nodes_.resize(node_count(n));
    for (int t = 1; t < thread_count(); t *= 2) ++split_depth_;
    build(0, 0, n, 0);
  }
  std::vector<GpuNode>& nodes() { return nodes_; }
  std::vector<GpuTri> tris() const {
    std::vector<GpuTri> out(items_.size());
    on_shares(out.size(), threads_for(out.size(), kItemsPerThread), [&](std::size_t b, std::size_t e) {
      for (std::size_t k = b; k < e; ++k) {
        const std::uint32_t f = items_[k].face;
        const Tri& t = mesh_.faces[f];
        const Vec3 a = mesh_.positions[t[0]], e1 = mesh_.positions[t[1]] - a, e2 = mesh_.positions[t[2]] - a;
        out[k] = {{float(a.x), float(a.y), float(a.z)},    f, {float(e1.x), float(e1.y), float(e1.z)}, 0,
                  {float(e2.x), float(e2.y), float(e2.z)}, 0};
      }
    });
    return out;
  }

 private:
  struct Item {
    float centroid[3];
    std::uint32_t face;
  };

  // Nodes of a subtree of n triangles: the split depends on n alone, so
  // that both halves can be built at once, each at its known place.
  std::size_t node_count(std::size_t n) {
    if (n <= kLeafSize) return 1;
    if (auto it = counts_.find(n); it != counts_.end()) return it->second;
    const std::size_t c = 1 + node_count(n / 2) + node_count(n - n / 2);
    counts_[n] = c;
    return c;
  }

  static void unite(GpuNode& box, const GpuNode& other) {
    for (int j = 0; j < 3; ++j) {
      box.lo[j] = std::min(box.lo[j], other.lo[j]);
      box.hi[j] = std::max(box.hi[j], other.hi[j]);
    }
  }

  void build(std::size_t node, std::size_t b, std::size_t e, int depth) {
    GpuNode& out = nodes_[node];
    const std::size_t n = e - b;
    if (n <= kLeafSize) {
      out = boxes_[items_[b].face];
      for (std::size_t k = b + 1; k < e; ++k) unite(out, boxes_[items_[k].face]);
      out.a = std::uint32_t(b);
      out.count = std::uint32_t(n);
      return;
    }
    float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF}, hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
    for (std::size_t k = b; k < e; ++k)
      for (int j = 0; j < 3; ++j) {
        lo[j] = std::min(lo[j], items_[k].centroid[j]);
        hi[j] = std::max(hi[j], items_[k].centroid[j]);
      }
    const float x = hi[0] - lo[0], y = hi[1] - lo[1], z = hi[2] - lo[2];
    const int axis = x >= y && x >= z ? 0 : y >= z ? 1 : 2;
    const std::size_t mid = b + n / 2;
    std::nth_element(items_.begin() + std::ptrdiff_t(b), items_.begin() + std::ptrdiff_t(mid),
                     items_.begin() + std::ptrdiff_t(e),
                     [axis](const Item& i, const Item& j) { return i.centroid[axis] < j.centroid[axis]; });
    const std::size_t left = node + 1, right = node + 1 + node_count(n / 2);
    // The top levels' halves on threads of their own (disjoint ranges and
    // nodes), a thread for each core.
    if (depth < split_depth_ && n > kItemsPerThread) {
      std::jthread other([&] { build(left, b, mid, depth + 1); });
      build(right, mid, e, depth + 1);
    } else {
      build(left, b, mid, depth + 1);
      build(right, mid, e, depth + 1);
    }
    out = nodes_[left];
    unite(out, nodes_[right]);
    out.a = std::uint32_t(right);
    out.count = 0;
  }

  const Mesh& mesh_;
  std::vector<Item> items_;
  std::vector<GpuNode> boxes_;  // each face's, padded
  std::vector<GpuNode> nodes_;
  std::map<std::size_t, std::size_t> counts_;
  int split_depth_ = 0;
};

}  // namespace

struct GpuRayCaster::Impl {
  SharedContext* shared = nullptr;
  static constexpr int kBuffers = 6;
  GLuint buffers[kBuffers] = {};  // nodes, triangles, rays, hits, frames, cone
  std::size_t bytes[kBuffers] = {};
  std::size_t max_batch = 0;  // rays a dispatch casts at most
  std::vector<Vec3> normals;  // each face's, for its hits (the shader returns the face alone)

  // Buffer k holding at least `size` bytes (grown, contents dropped).
  void reserve(const GlFunctions& gl, int k, std::size_t size) {
    if (bytes[k] >= size) return;
    gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[k]);
    gl.glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(size), nullptr, k == 3 ? GL_STREAM_READ : GL_STREAM_DRAW);
    bytes[k] = size;
  }
  // The rays of `count` items (rays, or frames of `per_item` rays each
  // with `cone` beside them) into hits as the shader writes them, item by
  // item in buffer `buffer`, in batches of at most max_batch rays.
  void cast(const void* items, std::size_t count, std::size_t item_bytes, int buffer, std::size_t per_item,
            std::span<const std::byte> cone, std::vector<GpuHit>& hits) {
    const std::size_t rays_per = std::max<std::size_t>(1, per_item);
    hits.resize(count * rays_per);
    if (hits.empty()) return;
    const Current current(*shared);
    const GlFunctions& gl = current.gl();
    const GlComputeFunctions& gc = current.gc();
    const std::size_t batch = std::min(count, std::max<std::size_t>(1, max_batch / rays_per));
    reserve(gl, buffer, batch * item_bytes);
    reserve(gl, 3, batch * rays_per * sizeof(GpuHit));
    if (!cone.empty()) {
      reserve(gl, 5, cone.size());
      gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[5]);
      gc.glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(cone.size()), cone.data());
    }
    current.check("allocating the ray buffers");
    gl.glUseProgram(shared->program);
    for (int k = 0; k < kBuffers; ++k) gc.glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GLuint(k), buffers[k]);
    gl.glUniform1ui(shared->cone_rays, GLuint(per_item));
    for (std::size_t b = 0; b < count; b += batch) {
      const std::size_t n = std::min(batch, count - b), rays = n * rays_per;
      gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[buffer]);
      gc.glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(n * item_bytes),
                         static_cast<const std::byte*>(items) + b * item_bytes);
      gl.glUniform1ui(shared->ray_count, GLuint(rays));
      gc.glDispatchCompute(GLuint((rays + kGroupSize - 1) / kGroupSize), 1, 1);
      gc.glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
      gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[3]);
      gc.glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(rays * sizeof(GpuHit)), hits.data() + b * rays_per);
      current.check("casting rays");
    }
    gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    gl.glUseProgram(0);
  }
};

GpuRayCaster::GpuRayCaster(const Mesh& mesh, GlPlatform platform) : impl_(std::make_unique<Impl>()) {
  if (mesh.faces.empty()) throw InvalidInput("GPU rays: the mesh has no faces");
  if (mesh.faces.size() >= std::size_t(kBehind)) throw InvalidInput("GPU rays: too many faces");
  SharedContext& s = shared_context(platform);
  {
    std::lock_guard lock(s.mutex);
    if (!s.context) s.context = std::make_unique<EglContext>(platform, render::GlVersion{4, 3});
  }
  if (!s.context->info().compute)
    throw Error("GPU rays: the OpenGL context (" + s.context->info().gl_renderer + ", " + s.context->info().gl_version +
                ") has no compute shaders (OpenGL 4.3)");
  impl_->shared = &s;
  impl_->normals = face_normals(mesh);

  BvhBuilder bvh(mesh);
  const std::vector<GpuTri> tris = bvh.tris();
  nodes_ = bvh.nodes().size();

  const Current current(s);
  const GlFunctions& gl = current.gl();
  const GlComputeFunctions& gc = current.gc();
  if (!s.program) {
    s.program = render::link_program(gl, {{GL_COMPUTE_SHADER, kShader}}, "GPU rays");
    s.ray_count = gl.glGetUniformLocation(s.program, "ray_count");
    s.cone_rays = gl.glGetUniformLocation(s.program, "cone_rays");
  }
  GLint64 max_block = 0;
  gc.glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
  const std::size_t largest = std::max(nodes_ * sizeof(GpuNode), tris.size() * sizeof(GpuTri));
  if (std::size_t(max_block) < largest)
    throw Error("GPU rays: the mesh's BVH needs storage buffers of " + std::to_string(largest >> 20) +
                " MiB, the driver allows " + std::to_string(std::size_t(max_block) >> 20) + " MiB");
  gl.glGenBuffers(Impl::kBuffers, impl_->buffers);
  const auto upload = [&](int k, std::size_t bytes, const void* data) {
    gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, impl_->buffers[k]);
    gl.glBufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(bytes), data, GL_STATIC_DRAW);
  };
  upload(0, nodes_ * sizeof(GpuNode), bvh.nodes().data());
  upload(1, tris.size() * sizeof(GpuTri), tris.data());
  impl_->max_batch = std::min<std::size_t>(kBatch, std::size_t(max_block) / sizeof(Ray));
  // Every binding backed by storage, the unused ones too.
  for (int k = 2; k < Impl::kBuffers; ++k) impl_->reserve(gl, k, 64);
  gl.glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  current.check("uploading the BVH");
}

GpuRayCaster::~GpuRayCaster() {
  if (!impl_->shared || !impl_->buffers[0]) return;
  try {
    const Current current(*impl_->shared);
    current.gl().glDeleteBuffers(Impl::kBuffers, impl_->buffers);
  } catch (...) {  // the context is gone: so are its buffers
  }
}

const std::vector<Vec3>& GpuRayCaster::normals() const { return impl_->normals; }

const render::EglInfo& GpuRayCaster::info() const { return impl_->shared->context->info(); }

void GpuRayCaster::first_hits(std::span<const Ray> rays, std::vector<Hit>& hits) const {
  std::vector<FaceHit> found;
  impl_->cast(rays.data(), rays.size(), sizeof(Ray), 2, 0, {}, found);
  hits.resize(found.size());
  for (std::size_t i = 0; i < found.size(); ++i) hits[i] = hit(found[i]);
}

void GpuRayCaster::cone_hits(std::span<const Frame> frames, std::span<const ConeRay> cone,
                             std::vector<FaceHit>& hits) const {
  impl_->cast(frames.data(), frames.size(), sizeof(Frame), 4, cone.size(),
              {reinterpret_cast<const std::byte*>(cone.data()), cone.size_bytes()}, hits);
}

GpuRayCaster::Hit GpuRayCaster::hit(const FaceHit& h) const {
  return h.met() ? Hit{double(h.distance), h.face_met(), impl_->normals[h.face_met()]} : Hit{};
}

std::vector<GpuRayCaster::Hit> GpuRayCaster::first_hits(std::span<const Ray> rays) const {
  std::vector<Hit> hits;
  first_hits(rays, hits);
  return hits;
}

}  // namespace cgview
