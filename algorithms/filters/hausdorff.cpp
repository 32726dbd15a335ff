#include "filters/hausdorff.h"

// The kernel first: distance.h calls CGAL::midpoint without including it.
#include "core/surface_mesh.h"
#include "filters/repair_mesh.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/distance.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace cgview {
namespace {

using Triangle = Kernel::Triangle_3;
using Tree = CGAL::AABB_tree<
    CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

}  // namespace

HausdorffResult hausdorff(const Mesh& a, const Mesh& b, const HausdorffParams& p, Context* context) {
  check_params(p);
  const Context& ctx = context_or_none(context);
  if (a.num_faces() == 0) throw InvalidInput("input 'mesh' has no faces");
  if (b.num_faces() == 0) throw InvalidInput("input 'reference' has no faces");
  ctx.progress(0, "converting");
  BBox box;
  for (const Vec3& v : a.positions) box.add(v);
  for (const Vec3& v : b.positions) box.add(v);
  const double diagonal = box.diagonal();
  // Non-manifold faces cannot enter a Surface_mesh, so the bound would leave
  // them out: a repaired copy holds them all (the repair moves no point and
  // removes only degenerate and duplicate faces), else refused.
  HausdorffResult result;
  const SurfaceMesh sa = halfedge_mesh_for(a, "hausdorff (input 'mesh')", p.repair, result.warnings),
                    sb = halfedge_mesh_for(b, "hausdorff (input 'reference')", p.repair, result.warnings);
  ctx.check_cancelled();

  // The per-vertex field: distance from each vertex of A to B's surface.
  ctx.progress(0.05, "vertex distances");
  std::vector<Triangle> triangles;
  triangles.reserve(b.num_faces());
  auto point = [](const Vec3& v) { return Point3(v.x, v.y, v.z); };
  for (const auto& f : b.faces)
    triangles.emplace_back(point(b.positions[f[0]]), point(b.positions[f[1]]), point(b.positions[f[2]]));
  Tree tree(triangles.begin(), triangles.end());
  tree.accelerate_distance_queries();
  ScalarField& field = result.distance;
  field = ScalarField{"distance", Location::vertex, ColorHint::magnitude, {}};
  field.values.resize(a.num_vertices());
  double sum = 0, sum2 = 0, vmax = 0;
  for (std::size_t i = 0; i < a.num_vertices(); ++i) {
    if (i % 4096 == 0) {
      ctx.check_cancelled();
      ctx.progress(0.05 + 0.25 * double(i) / double(a.num_vertices()), "vertex distances");
    }
    const double d = std::sqrt(CGAL::to_double(tree.squared_distance(point(a.positions[i]))));
    field.values[i] = float(d);
    sum += d;
    sum2 += d * d;
    vmax = std::max(vmax, d);
  }

  // The Hausdorff distance over the whole surfaces, in both directions.
  namespace PMP = CGAL::Polygon_mesh_processing;
  const double bound = p.error_bound * diagonal;
  ctx.progress(0.3, "mesh to reference");
  const double ab = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sa, sb, bound);
  ctx.check_cancelled();
  ctx.progress(0.65, "reference to mesh");
  const double ba = PMP::bounded_error_Hausdorff_distance<CGAL::Sequential_tag>(sb, sa, bound);

  const double n = double(std::max<std::size_t>(a.num_vertices(), 1));
  Metrics& m = result.metrics;
  m["hausdorff"] = std::max(ab, ba);
  m["mesh_to_reference"] = ab;
  m["reference_to_mesh"] = ba;
  m["hausdorff_relative"] = diagonal > 0 ? std::max(ab, ba) / diagonal : 0;
  m["error_bound"] = bound;
  m["bbox_diagonal"] = diagonal;
  m["vertex_distance_max"] = vmax;
  m["vertex_distance_mean"] = sum / n;
  m["vertex_distance_rms"] = std::sqrt(sum2 / n);
  ctx.progress(1.0, "done");
  return result;
}

// The inputs by name, "mesh" first (as its own statement: the order in which
// a call's arguments are evaluated is unspecified) so that a job missing both
// is told of "mesh".
CGVIEW_REGISTER_FUNCTION(
    hausdorff,
    [](const Inputs& in, const HausdorffParams& p, Context* c) {
      const Mesh& mesh = in.mesh("mesh");
      return hausdorff(mesh, in.mesh("reference"), p, c);
    },
    {.title = "Hausdorff distance",
     .description = "The symmetric Hausdorff distance between two meshes (exact within a "
                    "bound, over the whole surfaces), and each vertex's distance to the "
                    "reference as a colour map.",
     .area = "filters",
     .inputs = {{.name = "mesh", .kind = OutputKind::mesh, .help = "the mesh measured (it carries the colour map)"},
                {.name = "reference", .kind = OutputKind::mesh, .help = "the mesh it is compared with"}}})

}  // namespace cgview
