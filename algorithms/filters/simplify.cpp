// The quadrics are Eigen 4x4 matrices in a dynamic property map, whose
// default value GCC thinks may be read uninitialized: a false positive in
// Eigen's headers, silenced for them alone.
#include "filters/simplify.h"

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

namespace cgview {
namespace {

namespace SMS = CGAL::Surface_mesh_simplification;

// Counts faces as edges collapse (an interior edge takes two faces with it, a
// border edge one), reports progress and lets the stop predicate see a cancel.
struct Tracker {
  std::size_t faces = 0, initial = 0, target = 0, collapses = 0;
  const Context* ctx = nullptr;
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

}  // namespace

SimplifyResult simplify(const Mesh& mesh, const SimplifyParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (mesh.num_faces() == 0) throw InvalidInput("simplify needs a mesh with faces");
  ctx.progress(0, "converting");
  SimplifyResult result;
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
  result.mesh = from_surface_mesh(sm);
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(simplify, simplify,
                         {.title = "Simplify (quadric edge collapse)",
                          .description = "Decimates a manifold triangle mesh by edge collapses ordered by the "
                                         "Garland-Heckbert quadric error, down to a target face count or ratio.",
                          .area = "filters"})

}  // namespace cgview
