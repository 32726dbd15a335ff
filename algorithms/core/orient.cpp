#include "core/orient.h"

#include <utility>

#include "core/mesh_report.h"

namespace cgview {

void flip_faces(Mesh& mesh) {
  for (auto* faces : {&mesh.faces, &mesh.normal_faces, &mesh.uv_faces})
    for (Tri& t : *faces) std::swap(t[1], t[2]);
  for (Vec3f& n : mesh.normals) n = {-n.x, -n.y, -n.z};
}

bool orient_outward_in_place(Mesh& mesh) {
  if (!mesh_report(mesh).faces_inward) return false;
  flip_faces(mesh);
  return true;
}

}  // namespace cgview
