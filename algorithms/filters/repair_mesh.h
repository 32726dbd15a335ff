// The clean-up of the `repair` filter as a function, shared by the
// algorithms that need a halfedge structure and take a `repair` parameter
// (filters/repair_param.h).
//
// CGAL's polygon soup tools: merge_duplicate_points_in_polygon_soup, zero-area
// faces removed by an exact collinearity test, repair_polygon_soup (degenerate
// and duplicate faces, isolated points), orient_polygon_soup (duplicates the
// points at non-manifold edges and vertices so the faces orient
// consistently), polygon_soup_to_polygon_mesh, and optionally stitch_borders.
// Include only in .cpp files: it brings CGAL's headers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/surface_mesh.h"

namespace cgview {

struct RepairReport {
  std::size_t vertices_before = 0, faces_before = 0;
  std::size_t vertices_merged = 0;  // duplicate points merged
  std::size_t faces_removed = 0;    // degenerate, zero-area and duplicate faces
  std::size_t isolated_vertices_removed = 0;
  std::size_t vertices_duplicated = 0;  // to split non-manifold edges and vertices
  std::size_t borders_stitched = 0;
};

// The repaired mesh as a Surface_mesh (garbage collected); vertex indices are
// not those of the input.  Throws InvalidInput when every face is degenerate.
SurfaceMesh repair_to_surface_mesh(const Mesh& mesh, bool stitch, RepairReport& report);

// For an algorithm WHO that needs a halfedge structure: the Surface_mesh of
// `mesh` as it is when it fits one; else, when `repair` is set, of a
// repaired copy (`mesh` itself is never changed), with a warning saying
// what the repair changed ("WHO: the mesh was not manifold (...) and a copy
// was repaired first: 4 vertices duplicated to split non-manifold edges and
// vertices, 1 degenerate or duplicate face removed"), and `*repaired` set;
// else InvalidInput naming the precondition and the `repair` parameter.
SurfaceMesh halfedge_mesh_for(const Mesh& mesh, const char* who, bool repair, std::vector<std::string>& warnings,
                              bool* repaired = nullptr);

// Where the elements of `mesh` went in `repaired` (repair_to_surface_mesh's
// or halfedge_mesh_for's), found by position, as the repair moves no point.
// For each face of `mesh`: the face of `repaired` with the same three
// corners (in any order), or -1 for a face the repair removed (degenerate);
// duplicate faces find the same face.
std::vector<std::int64_t> faces_after_repair(const Mesh& mesh, const SurfaceMesh& repaired);
// For each vertex of `mesh`: the vertices of `repaired` at its position
// (several where the repair split a non-manifold vertex, none for an
// isolated vertex it removed).
std::vector<std::vector<SurfaceMesh::Vertex_index>> vertices_after_repair(const Mesh& mesh,
                                                                          const SurfaceMesh& repaired);

}  // namespace cgview
