// simplify: edge-collapse decimation with Garland–Heckbert quadric error
// metrics (Garland and Heckbert 1997), CGAL's Surface_mesh_simplification.
// The quadrics are Eigen 4x4 matrices in a dynamic property map, whose
// default value GCC thinks may be read uninitialized: a false positive in
// Eigen's headers, silenced for them alone.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Surface_mesh_simplification/Edge_collapse_visitor_base.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;

struct Params {
  bool repair = false;
  int target_faces = 0;
  double ratio = 0.5;
  template <class V>
  void describe(V& v) {
    v.integer(
        "target_faces", target_faces,
        {.label = "Target faces",
         .min = 0,
         .max = 1e9,
         .help = "stop at this many faces or fewer; 0 means use the ratio (when above 0, it wins over the ratio)"});
    v.number("ratio", ratio,
             {.label = "Ratio",
              .min = 0,
              .max = 1,
              .help = "fraction of the input's faces to keep, used when target_faces is 0"});
    v.boolean(
        "repair", repair,
        {.label = "Repair first",
         .help = "when the mesh is not manifold, repair it first (as the repair filter does) instead of refusing it"});
  }
};

// Counts faces as edges collapse (an interior edge takes two faces with it, a
// border edge one), reports progress and lets the stop predicate see a cancel.
struct Tracker {
  std::size_t faces = 0, initial = 0, target = 0, collapses = 0;
  Context* ctx = nullptr;
};

struct Visitor : SMS::Edge_collapse_visitor_base<SurfaceMesh> {
  Tracker* t;
  explicit Visitor(Tracker* tracker) : t(tracker) {}
  template <class Profile, class VD>
  void OnCollapsed(const Profile& p, const VD&) {
    t->faces -= std::size_t(p.left_face_exists()) + std::size_t(p.right_face_exists());
    if (++t->collapses % 256 == 0)
      t->ctx->progress(0.05 + 0.9 * double(t->initial - t->faces) / double(t->initial - t->target), "collapsing edges");
  }
};

struct Stop {
  Tracker* t;
  template <class F, class Profile>
  bool operator()(const F&, const Profile&, std::size_t, std::size_t) const {
    return t->faces <= t->target || t->ctx->cancelled();
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("simplify needs a mesh with faces");
  ctx.progress(0, "converting");
  AlgorithmResult result;
  SurfaceMesh sm = halfedge_mesh_for(mesh, "simplify", p.repair, result.warnings);
  Tracker t;
  t.faces = t.initial = sm.number_of_faces();
  t.target = p.target_faces > 0 ? std::size_t(p.target_faces) : std::size_t(std::llround(p.ratio * double(t.initial)));
  t.ctx = &ctx;
  if (t.target < t.initial) {
    SMS::GarlandHeckbert_plane_policies<SurfaceMesh, Kernel> gh(sm);
    SMS::edge_collapse(
        sm, Stop{&t}, CGAL::parameters::get_cost(gh.get_cost()).get_placement(gh.get_placement()).visitor(Visitor(&t)));
    ctx.check_cancelled();
    sm.collect_garbage();
    if (sm.number_of_faces() > t.target)
      result.warnings.push_back("stopped at " + std::to_string(sm.number_of_faces()) +
                                " faces: no more edges could be collapsed without breaking the mesh");
  }
  result.artifacts.push_back({"mesh", from_surface_mesh(sm)});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(simplify, Params, run,
                          {.title = "Simplify (quadric edge collapse)",
                           .description = "Decimates a manifold triangle mesh by edge collapses ordered by the "
                                          "Garland-Heckbert quadric error, down to a target face count or ratio.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}}})

}  // namespace
}  // namespace cgview
