// repair: cleans a triangle soup and rebuilds a manifold mesh from it, with
// CGAL's polygon soup tools.  It works on the soup, so it accepts what no
// halfedge structure can hold (three faces on an edge, a bowtie vertex):
// repair_polygon_soup merges duplicate points and removes degenerate (here
// also zero-area) and duplicate faces and isolated points, orient_polygon_soup duplicates the
// points at non-manifold edges and vertices so the faces can be oriented
// consistently, and stitch_borders glues border edges that coincide.
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>

#include <string>
#include <vector>

#include "core/mesh_report.h"
#include "core/surface_mesh.h"
#include "registry/registry.h"

namespace cgview {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;

struct Params {
  bool stitch = true;
  template <class V>
  void describe(V& v) {
    v.boolean("stitch", stitch,
              {.label = "Stitch borders", .help = "glue border edges whose end points coincide"});
  }
};

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  if (mesh.num_faces() == 0) throw InvalidInput("repair needs a mesh with faces");
  ctx.progress(0, "checking");
  const MeshReport before = mesh_report(mesh);
  std::vector<Point3> points;
  points.reserve(mesh.num_vertices());
  for (const Vec3& v : mesh.positions) points.emplace_back(v.x, v.y, v.z);
  std::vector<std::vector<std::size_t>> polygons;
  polygons.reserve(mesh.num_faces());
  for (const Tri& f : mesh.faces) polygons.push_back({f[0], f[1], f[2]});
  const std::size_t points0 = points.size(), faces0 = polygons.size();

  ctx.progress(0.1, "repairing the soup");
  const std::size_t merged = PMP::merge_duplicate_points_in_polygon_soup(points, polygons);
  // repair_polygon_soup removes faces with fewer than three distinct points;
  // faces of zero area (three collinear points) go here, by an exact test.
  std::erase_if(polygons, [&](const std::vector<std::size_t>& f) {
    return CGAL::collinear(points[f[0]], points[f[1]], points[f[2]]);
  });
  const std::size_t points1 = points.size();
  PMP::repair_polygon_soup(points, polygons);
  const std::size_t isolated = points1 - points.size();
  const std::size_t faces_removed = faces0 - polygons.size();
  if (polygons.empty()) throw InvalidInput("repair: every face is degenerate");
  ctx.check_cancelled();

  ctx.progress(0.4, "orienting");
  const std::size_t points2 = points.size();
  PMP::orient_polygon_soup(points, polygons);
  const std::size_t duplicated = points.size() - points2;
  ctx.check_cancelled();

  ctx.progress(0.6, "building the mesh");
  if (!PMP::is_polygon_soup_a_polygon_mesh(polygons))
    throw InvalidInput("repair: the oriented soup is still not a polygon mesh");
  SurfaceMesh sm;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
  std::size_t stitched = 0;
  if (p.stitch) {
    ctx.progress(0.8, "stitching borders");
    stitched = PMP::stitch_borders(sm);
    sm.collect_garbage();
  }
  Mesh out = from_surface_mesh(sm);
  const MeshReport after = mesh_report(out);

  AlgorithmResult result;
  result.artifacts.push_back({"mesh", std::move(out)});
  result.artifacts.push_back({"metrics", Metrics{
                                             {"faces_removed", double(faces_removed)},
                                             {"vertices_merged", double(merged)},
                                             {"isolated_vertices_removed", double(isolated)},
                                             {"vertices_duplicated", double(duplicated)},
                                             {"borders_stitched", double(stitched)},
                                             {"vertices_before", double(points0)},
                                             {"vertices_after", double(after.vertices)},
                                             {"faces_before", double(faces0)},
                                             {"faces_after", double(after.faces)},
                                             {"manifold_before", before.manifold ? 1.0 : 0.0},
                                             {"manifold_after", after.manifold ? 1.0 : 0.0},
                                             {"closed_before", before.closed ? 1.0 : 0.0},
                                             {"closed_after", after.closed ? 1.0 : 0.0},
                                         }});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(repair, Params, run,
                          {.title = "Repair (soup clean-up, orient, stitch)",
                           .description = "Merges duplicate points, removes degenerate and duplicate faces and "
                                          "isolated points, splits non-manifold edges and vertices so the faces "
                                          "can be oriented, then stitches coinciding borders. Accepts non-manifold "
                                          "input.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
