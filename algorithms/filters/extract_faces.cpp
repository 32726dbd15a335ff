// extract_faces: the selected faces of a mesh as a mesh of their own (or,
// with invert, the mesh without them): MeshLab's "Move selected faces to
// another layer" / "Delete selected faces".  It is the example of an
// algorithm that takes the viewer's selection as an input (a faces
// parameter, see registry.h).
#include <vector>

#include "registry/registry.h"

namespace cgview {
namespace {

struct Params {
  Ids faces;
  bool invert = false;
  template <class V>
  void describe(V& v) {
    v.faces("faces", faces, {.label = "Faces", .help = "the ids of the faces to extract (the viewer's selection)"});
    v.boolean("invert", invert, {.label = "Delete instead", .help = "keep the other faces: delete the selected ones"});
  }
};

// The faces kept, in their original order, with the vertices they use
// (renumbered in order of first use by the kept faces' original order: the
// vertex order of the input is kept).  Per-vertex attributes follow their
// vertex; indexed normals and UVs follow their face.
Mesh keep_faces(const Mesh& mesh, const std::vector<bool>& keep) {
  Mesh out;
  std::vector<Index> new_id(mesh.num_vertices(), Index(-1));
  std::vector<bool> used(mesh.num_vertices(), false);
  for (std::size_t f = 0; f < mesh.num_faces(); ++f)
    if (keep[f])
      for (const Index v : mesh.faces[f]) used[v] = true;
  const bool vertex_normals = mesh.has_normals() && mesh.normal_faces.empty();
  const bool vertex_uvs = mesh.has_uvs() && mesh.uv_faces.empty();
  for (std::size_t v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[v]) continue;
    new_id[v] = Index(out.positions.size());
    out.positions.push_back(mesh.positions[v]);
    if (vertex_normals) out.normals.push_back(mesh.normals[v]);
    if (vertex_uvs) out.uvs.push_back(mesh.uvs[v]);
    if (mesh.has_colors()) out.colors.push_back(mesh.colors[v]);
  }
  if (!vertex_normals) out.normals = mesh.normals;
  if (!vertex_uvs) out.uvs = mesh.uvs;
  for (std::size_t f = 0; f < mesh.num_faces(); ++f) {
    if (!keep[f]) continue;
    const Tri& t = mesh.faces[f];
    out.faces.push_back({new_id[t[0]], new_id[t[1]], new_id[t[2]]});
    if (!mesh.normal_faces.empty()) out.normal_faces.push_back(mesh.normal_faces[f]);
    if (!mesh.uv_faces.empty()) out.uv_faces.push_back(mesh.uv_faces[f]);
  }
  return out;
}

AlgorithmResult run(const Mesh& mesh, const Params& p, Context& ctx) {
  mesh.validate();
  if (p.faces.empty()) throw InvalidInput("parameter 'faces': select at least one face");
  ctx.progress(0.0, "extracting");
  std::vector<bool> keep(mesh.num_faces(), p.invert);
  for (const Index f : p.faces) keep[f] = !p.invert;  // in range: the registry checked them
  Mesh out = keep_faces(mesh, keep);
  AlgorithmResult result;
  double area = 0;
  for (const double a : face_areas(out)) area += a;
  Metrics m{{"faces", double(out.num_faces())}, {"vertices", double(out.num_vertices())}, {"area", area}};
  result.artifacts.push_back({"mesh", std::move(out)});
  result.artifacts.push_back({"metrics", std::move(m)});
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_ALGORITHM(extract_faces, Params, run,
                          {.title = "Extract selected faces",
                           .description = "The selected faces as a new mesh with only the vertices they use (or, with "
                                          "'delete instead', the mesh without them). Face order is kept.",
                           .area = "filters",
                           .outputs = {{"mesh", OutputKind::mesh}, {"metrics", OutputKind::metrics}}})

}  // namespace
}  // namespace cgview
