// Saving an algorithm's artifacts in formats that common tools read, by
// each kind's codec (artifacts/artifact_codec.h lists the formats), and
// reading a run's input files.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "registry/registry.h"

namespace cgview {

// The extension used when the caller names none (".ply", ".txt", ...).
std::string default_extension(const Artifact& artifact);
// Writes the artifact; `input` is the mesh the algorithm ran on (for a
// field saved as .ply).  Throws UnsupportedFormat for an extension the
// artifact's kind cannot be saved as.
void write_artifact(const Artifact& artifact, const Mesh& input, const std::filesystem::path& path);
// Throws UnsupportedFormat, as write_artifact would, unless an artifact of
// that kind can be saved under path's extension: `cgview run` checks its -o
// before a long run rather than after.
void check_artifact_extension(OutputKind kind, const std::filesystem::path& path);

// The files of one run's inputs, each read as the kind its InputSpec
// declares: a mesh file, a voxel grid file (voxel/voxel_io.h), a skeleton
// file (io/skeleton_io.h), or a point cloud (any mesh file: its vertices).
// Owns what it read; inputs() refers to it.  Used by `cgview run` and
// cgview-worker alike.
class InputFiles {
 public:
  // Reads `path` as input `spec`; returns the mesh reader's warnings (what
  // was repaired or dropped), none for the other kinds.  Throws what the
  // readers throw.
  std::vector<std::string> read(const InputSpec& spec, const std::filesystem::path& path);
  const Inputs& inputs() const { return inputs_; }
  // The first mesh read (per-vertex artifacts are saved on it), else an empty mesh.
  const Mesh& primary_mesh() const;

 private:
  std::map<std::string, Mesh> meshes_;
  std::map<std::string, VoxelGrid> grids_;
  std::map<std::string, Skeleton> skeletons_;
  std::map<std::string, PointCloud> clouds_;
  Inputs inputs_;
  const Mesh* primary_ = nullptr;
};

}  // namespace cgview
