// One home per artifact kind.  An algorithm's result of one kind (a mesh, a
// scalar field, a voxel grid, a skeleton, metrics, text, an animation) is
// stored in a job's directory, read back, and exported in the formats that
// other tools read, by that kind's codec alone:
//
//   kind          stored as       exported as
//   mesh          NAME.ply        ply off obj stl glb drc
//   scalar_field  NAME.f32 (+ NAME.field.json)
//                                 json f32 (served only), txt csv ply (the input mesh with the values)
//   voxel_grid    NAME.nrrd       nrrd binvox vti vox vdb vtk (raw: a file and its .json, `cgview run` only)
//   skeleton      NAME.obj        obj cg json polylines (.polylines.txt)
//   metrics       NAME.json       json
//   text          NAME.txt        txt bin (the bytes as they are)
//   animation     NAME.frames     frames (core/animation.h)
//   vector_field  NAME.vec.f32    json f32 (served only), csv ply (points with the vectors as normals) vtk
//   points        NAME.ply        drc (served by default: the viewer's) ply xyz
//
// cgview-worker stores its results with store(), `cgview run` writes its -o
// files with write(), and the server serves `?format=` with exported() and
// reads fields, grids and animations back with load().  A new kind is one
// file here (its codec) and one line in artifact_codec.cpp's table.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "registry/registry.h"

namespace cgview {

using ArtifactValue = decltype(Artifact::value);

struct ArtifactFormat {
  std::string name;          // what ?format= takes ("polylines")
  std::string extension;     // what a file in it ends with (".polylines.txt")
  std::string content_type;  // as served over HTTP
  bool served = true;        // false: a file only (several files, as .raw and its .json)
  bool written = true;       // false: served only, never a file of `cgview run` (a field's f32 and json)
};

// An artifact's bytes in one format, as the server sends them.
struct ExportedArtifact {
  std::string bytes, content_type, file_name;
};

class ArtifactCodec {
 public:
  virtual ~ArtifactCodec() = default;
  virtual OutputKind kind() const = 0;
  // Every format it is exported in; the first is its stored form's.
  virtual const std::vector<ArtifactFormat>& formats() const = 0;
  // The format served when none is asked for (`?format=` left out).
  virtual std::string served_default() const { return formats().front().name; }
  // The extension of a file whose caller named none (`cgview run` without -o).
  virtual std::string default_extension() const { return formats().front().extension; }
  // The artifact in `format` (one of formats()); `input` is the mesh it was
  // computed on (a field as PLY is that mesh with the values).  Throws
  // UnsupportedFormat for another format.
  virtual std::string encode(const ArtifactValue& value, const std::string& name, const Mesh& input,
                             const ArtifactFormat& format) const = 0;
  // Whether `format` is written over the mesh the artifact was computed on
  // (a field as PLY), which exported() then reads.
  virtual bool needs_mesh(const ArtifactFormat&) const { return false; }
  // The stored form's bytes read back.  Throws ParseError for bytes that
  // are not one.
  virtual ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json& entry) const = 0;

  // Writes the stored form into `dir` (NAME + the stored extension) and
  // returns its entry in the job's artifact list: {"name", "kind", "file",
  // "bytes" (the file's size as written)} and the kind's own fields.
  virtual nlohmann::json store(const Artifact& a, const Mesh& input, const std::filesystem::path& dir) const;
  // The files store() writes beside the entry's "file" that load() reads
  // when they are there (a field's own name in NAME.field.json): the
  // server takes them out of a job's directory with the file.
  virtual std::vector<std::string> side_files(const nlohmann::json&) const { return {}; }
  // Reads a stored artifact back, as its `entry` describes it.
  virtual ArtifactValue load(const std::filesystem::path& dir, const nlohmann::json& entry) const;
  // Writes the artifact to `path` in the format its extension names.
  virtual void write(const Artifact& a, const Mesh& input, const std::filesystem::path& path) const;
  // The format a path's extension names; throws UnsupportedFormat listing the known ones.
  virtual const ArtifactFormat& format_of_path(const std::filesystem::path& path) const;
  // The format ?format= names ("": served_default()); throws UnsupportedFormat.
  const ArtifactFormat& format_named(std::string name) const;
  // A stored artifact in `format` ("": served_default()): the stored file
  // as it is where it is that format, else read back and encoded.
  // `input_mesh` is called only for a format that needs the mesh.
  ExportedArtifact exported(const std::filesystem::path& dir, const nlohmann::json& entry, const std::string& format,
                            const std::function<Mesh()>& input_mesh) const;

 protected:
  // "a scalar field" (for messages).
  std::string noun() const;
  // The served formats as a user reads them: "f32, json, txt, csv or ply".
  std::string format_list(bool served_only) const;
};

// Appends a number in the fewest digits that read back as the same double
// (the text formats of fields).
void append_shortest(std::string& s, double v);

// The codec of a kind, and of a kind's name ("scalar_field"; nullptr for an unknown one).
const ArtifactCodec& artifact_codec(OutputKind kind);
const ArtifactCodec* artifact_codec(std::string_view kind_name);
// The kind an artifact's value is.
OutputKind kind_of(const ArtifactValue& value);

}  // namespace cgview
