#include "rays/ray_caster.h"

#include <embree3/rtcore.h>

#include <utility>
#include <string>

#include "core/errors.h"
#include "core/shared_library.h"

namespace cgview {
namespace {

// Directions away from the axes, so that a grid-aligned mesh's edges are not
// grazed.
const Vec3 kInsideDirections[3] = {{0.5773, 0.5774, 0.5775}, {-0.8017, 0.2673, 0.5345}, {0.2182, -0.8729, 0.4364}};

// An intersection context that remembers the face a ray starts from, so that
// the filter below can skip it (CGAL's SkipPrimitiveFunctor).
struct SkipContext {
  RTCIntersectContext context;
  unsigned skip;
};

void skip_origin_face(const RTCFilterFunctionNArguments* args) {
  const auto* c = reinterpret_cast<const SkipContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] == -1 && RTCHitN_primID(args->hit, args->N, i) == c->skip) args->valid[i] = 0;
}

// Embree's functions, from the library opened by the first ray caster:
// linked in, its eager binding (15,000 relocations, -z now) cost every
// start of a job's worker, for the jobs that cast rays alone.
// clang-format off
#define CGVIEW_EMBREE_FUNCTIONS(X)                                                              \
  X(rtcNewDevice) X(rtcReleaseDevice) X(rtcGetDeviceError) X(rtcNewScene) X(rtcReleaseScene)    \
  X(rtcSetSceneFlags) X(rtcSetSceneBuildQuality) X(rtcNewGeometry) X(rtcReleaseGeometry)        \
  X(rtcSetNewGeometryBuffer) X(rtcCommitGeometry) X(rtcAttachGeometry) X(rtcCommitScene)        \
  X(rtcIntersect1)
// clang-format on
struct Embree {
#define CGVIEW_EMBREE_MEMBER(f) decltype(&::f) f = nullptr;
  CGVIEW_EMBREE_FUNCTIONS(CGVIEW_EMBREE_MEMBER)
#undef CGVIEW_EMBREE_MEMBER
};

const Embree& embree() {
  static const std::pair<Embree, std::string> loaded = [] {
    SharedLibrary lib(CGVIEW_LIBEMBREE);
    Embree e;
#define CGVIEW_EMBREE_FIND(f) e.f = lib.function<decltype(&::f)>(#f);
    CGVIEW_EMBREE_FUNCTIONS(CGVIEW_EMBREE_FIND)
#undef CGVIEW_EMBREE_FIND
    return std::pair(e, lib.why());
  }();
  if (!loaded.second.empty()) throw Error("cannot load Embree: " + loaded.second);
  return loaded.first;
}

}  // namespace

struct RayCaster::Impl {
  const Embree& rtc = embree();
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtc.rtcReleaseScene(scene);
    if (device) rtc.rtcReleaseDevice(device);
  }
};

RayCaster::RayCaster(const Mesh& mesh) : impl_(std::make_unique<Impl>()), normals_(face_normals(mesh)) {
  Impl& s = *impl_;
  const Embree& rtc = s.rtc;
  s.device = rtc.rtcNewDevice(nullptr);
  if (!s.device) throw Error("Embree could not start: error " + std::to_string(int(rtc.rtcGetDeviceError(nullptr))));
  s.scene = rtc.rtcNewScene(s.device);
  rtc.rtcSetSceneFlags(s.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  rtc.rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry g = rtc.rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtc.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                            3 * sizeof(float), mesh.positions.size()));
  auto* f = static_cast<unsigned*>(rtc.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), mesh.faces.size()));
  if (!v || !f) {
    rtc.rtcReleaseGeometry(g);
    throw Error("Embree could not allocate the mesh's buffers");
  }
  for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
    v[3 * i] = float(mesh.positions[i].x);
    v[3 * i + 1] = float(mesh.positions[i].y);
    v[3 * i + 2] = float(mesh.positions[i].z);
  }
  for (std::size_t i = 0; i < mesh.faces.size(); ++i)
    for (int k = 0; k < 3; ++k) f[3 * i + k] = unsigned(mesh.faces[i][k]);
  rtc.rtcCommitGeometry(g);
  rtc.rtcAttachGeometry(s.scene, g);
  rtc.rtcReleaseGeometry(g);
  rtc.rtcCommitScene(s.scene);
  if (rtc.rtcGetDeviceError(s.device) != RTC_ERROR_NONE) throw Error("Embree could not build the mesh's BVH");
  // Which way the faces face: from outside the bounding box along each
  // direction, whether the first face met faces the ray's origin.
  const BBox box = bounding_box(mesh);
  int out = 0, in = 0;
  for (const Vec3& d : kInsideDirections)
    if (const Hit h = first_hit(box.center() - d * (box.diagonal() + 1), d)) ++(dot(d, h.normal) < 0 ? out : in);
  faces_out_ = out >= in;
}

RayCaster::~RayCaster() = default;

RayCaster::Hit RayCaster::first_hit(const Vec3& origin, const Vec3& direction, std::uint32_t skip,
                                    double max_distance) const {
  const double length = norm(direction);
  if (!(length > 0)) return {};
  const Vec3 d = direction / length;
  SkipContext sc;
  rtcInitIntersectContext(&sc.context);
  sc.context.filter = skip_origin_face;
  sc.skip = skip;
  RTCRayHit rh{};
  rh.ray.org_x = float(origin.x), rh.ray.org_y = float(origin.y), rh.ray.org_z = float(origin.z);
  rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = max_distance < 3.0e38 ? float(max_distance) : std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  impl_->rtc.rtcIntersect1(impl_->scene, &sc.context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {};
  return {double(rh.ray.tfar), rh.hit.primID, {double(rh.hit.Ng_x), double(rh.hit.Ng_y), double(rh.hit.Ng_z)}};
}

bool RayCaster::inside(const Vec3& p) const {
  // The majority of three: the third ray only when the first two disagree.
  int votes = 0;
  for (int k = 0; k < 3; ++k) {
    const Hit h = first_hit(p, kInsideDirections[k]);
    if (h && (dot(kInsideDirections[k], h.normal) > 0) == faces_out_) ++votes;
    if (k == 1 && votes != 1) break;  // the first two agree
  }
  return votes >= 2;
}

}  // namespace cgview
