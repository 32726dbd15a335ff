#include "registry/artifact_io.h"

#include "artifacts/artifact_codec.h"
#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "voxel/voxel_io.h"

namespace cgview {

std::string default_extension(const Artifact& a) { return artifact_codec(kind_of(a.value)).default_extension(); }

void check_artifact_extension(OutputKind kind, const std::filesystem::path& path) {
  artifact_codec(kind).format_of_path(path);
}

void write_artifact(const Artifact& a, const Mesh& input, const std::filesystem::path& path) {
  artifact_codec(kind_of(a.value)).write(a, input, path);
}

std::vector<std::string> InputFiles::read(const InputSpec& spec, const std::filesystem::path& path) {
  switch (spec.kind) {
    case OutputKind::voxel_grid:
      inputs_.add(spec.name, grids_.insert_or_assign(spec.name, read_voxel_grid(path)).first->second);
      return {};
    case OutputKind::skeleton:
      inputs_.add(spec.name, skeletons_.insert_or_assign(spec.name, read_skeleton(path)).first->second);
      return {};
    case OutputKind::points: {
      // Any mesh file: a cloud's file is a mesh with no faces, and a mesh with faces gives its vertices.
      ReadResult r = read_mesh_file(path);
      inputs_.add(spec.name, clouds_.insert_or_assign(spec.name, points_of(r.mesh)).first->second);
      return std::move(r.warnings);
    }
    default: {
      ReadResult r = read_mesh_file(path);
      if (r.mesh.num_faces() == 0 && !spec.faceless)
        throw InvalidInput("input '" + spec.name + "' (" + path.filename().string() + ") is a point cloud of " +
                           std::to_string(r.mesh.num_vertices()) +
                           " points and no faces: this algorithm needs a mesh with faces");
      const Mesh& m = meshes_.insert_or_assign(spec.name, std::move(r.mesh)).first->second;
      inputs_.add(spec.name, m);
      if (!primary_) primary_ = &m;
      return std::move(r.warnings);
    }
  }
}

const Mesh& InputFiles::primary_mesh() const {
  static const Mesh no_mesh;
  return primary_ ? *primary_ : no_mesh;
}

}  // namespace cgview
