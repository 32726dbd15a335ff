// The one place where a Mesh becomes a CGAL::Surface_mesh and back.  Include
// this only in .cpp files of algorithms that use CGAL: it pulls in CGAL's
// headers, which cost seconds to compile.
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include "core/mesh.h"

namespace cgview {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point3 = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point3>;

struct SurfaceMeshResult {
  SurfaceMesh mesh;
  // Faces that a halfedge structure cannot hold (non-manifold, or degenerate)
  // are left out, counted here; vertices keep their indices.
  std::size_t skipped_faces = 0;
};

// For algorithms that need halfedges: the Surface_mesh of a mesh that fits
// one, else InvalidInput "WHO needs a manifold mesh: N faces could not be
// placed in a halfedge structure (non-manifold or degenerate); REMEDY".
SurfaceMesh manifold_surface_mesh(const Mesh& mesh, const char* who, const char* remedy = "run repair on it first");

// Vertices keep their indices; per-vertex normals and colours go into the
// property maps "v:normal" (Kernel::Vector_3) and "v:color" (CGAL::IO::Color).
SurfaceMeshResult to_surface_mesh(const Mesh& mesh);
// Garbage-free copy back (call collect_garbage() first if elements were removed).
Mesh from_surface_mesh(const SurfaceMesh& sm);

}  // namespace cgview
