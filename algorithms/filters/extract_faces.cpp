#include "filters/extract_faces.h"

namespace cgview {
namespace {

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

}  // namespace

ExtractFacesResult extract_faces(const Mesh& mesh, const ExtractFacesParams& p, Context* context) {
  const Context& ctx = context_or_none(context);
  mesh.validate();
  if (p.faces.empty()) throw InvalidInput("parameter 'faces': select at least one face");
  // A job's ids were checked against its mesh already; a direct call's are
  // checked here (with the parameters' ranges), by the same rule and message,
  // before they index `keep`.
  check_params(p, mesh);
  ctx.progress(0.0, "extracting");
  std::vector<bool> keep(mesh.num_faces(), p.invert);
  for (const Index f : p.faces) keep[f] = !p.invert;
  ExtractFacesResult result;
  result.mesh = keep_faces(mesh, keep);
  double area = 0;
  for (const double a : face_areas(result.mesh)) area += a;
  result.metrics = Metrics{
      {"faces", double(result.mesh.num_faces())}, {"vertices", double(result.mesh.num_vertices())}, {"area", area}};
  ctx.progress(1.0, "done");
  return result;
}

CGVIEW_REGISTER_FUNCTION(extract_faces, extract_faces,
                         {.title = "Extract selected faces",
                          .description = "The selected faces as a new mesh with only the vertices they use (or, with "
                                         "'delete instead', the mesh without them). Face order is kept.",
                          .area = "filters"})

}  // namespace cgview
