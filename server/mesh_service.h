// What the server does with meshes, independent of HTTP and WebSocket:
// parse and report uploads, store them, and produce their bytes in other
// formats, with the Draco encodings cached by content (a second fetch of
// the same mesh at the same quantization costs no encoding, and concurrent
// requests for one encoding share a single computation).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <future>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh.h"
#include "store.h"
#include "upload_read.h"

namespace cgview::server {

struct EncodedMesh {
  std::string bytes;  // the Draco bitstream
  std::uint64_t vertices = 0, faces = 0;
  bool has_normals = false, has_colors = false;
  // The stored vertex of each streamed point and the stored face of each
  // streamed face, packed (protocol/stored_order.h): made on first request.
  mutable std::once_flag stored_order_once;
  mutable std::string stored_order;
};

// When a mesh gets a preview (a coarse version streamed before it): more
// faces than threshold_faces (0: never), decimated to at most target_faces.
struct PreviewConfig {
  std::size_t threshold_faces = 200000;
  std::size_t target_faces = 80000;
};

// Throws InvalidInput unless bits is a Draco position quantization (1..30).
void check_quantization_bits(int bits);

class MeshService {
 public:
  explicit MeshService(Store& store, std::size_t cache_bytes = std::size_t(512) << 20);

  // Parses the bytes (format given, or from the name's extension; in a child
  // process when set_reader gave a program), computes the report and stores
  // it, owned by `owner`.  Throws InvalidInput (bad
  // name, format or file).  A zip ("x.zip" or format "zip") holds one mesh
  // file and what it refers to: an OBJ's MTL and its materials' map_Kd
  // images, a PLY's `comment TextureFile` image; each image is stored as a
  // blob of the mesh, and an OBJ's `materials` say which faces use which.
  // A referenced file that is missing is a warning, not an error.  Throws
  // TooLarge when the zip unpacks past max_upload_bytes, or its reading goes
  // past the reader's memory or time limit (upload_read.h).
  MeshRecord upload(const std::string& name, const std::string& format, std::string_view bytes,
                    const std::string& owner = "local");
  // The mesh, parsed from its stored bytes (the last few are kept in memory).
  std::shared_ptr<const Mesh> mesh(const MeshRecord& record);
  // The Draco encoding at a position quantization (1..30 bits).
  std::shared_ptr<const EncodedMesh> draco(const MeshRecord& record, int position_bits);
  // The stored vertex of each point and the stored face of each face of
  // draco(record, position_bits), packed (protocol/stored_order.h): what
  // lets the viewer colour fields and select on the one mesh it streamed.
  std::string stored_order(const MeshRecord& record, int position_bits);
  // Whether the mesh is big enough to get a preview (its report's face count).
  bool has_preview(const MeshRecord& record) const;
  // The preview's Draco encoding (14 bits): the mesh decimated by vertex
  // clustering (core/cluster_decimate.h), made on first request, stored as
  // a blob of the mesh (Store::write_preview) and kept in the encoding cache.
  // Throws InvalidInput when the mesh gets no preview.
  std::shared_ptr<const EncodedMesh> preview(const MeshRecord& record);
  // The mesh in a writable format ("obj", "ply", ...): the stored bytes
  // when the format is the uploaded one, else a conversion.
  std::string download(const MeshRecord& record, const std::string& format);
  // Uploads each mesh file that is not stored yet (by content), skipping
  // files it cannot read; returns how many were added.  Samples belong to
  // kSystemOwner and are shared with everyone.
  int import_samples(const std::vector<std::filesystem::path>& files, std::size_t max_bytes_each);

  Store& store() { return store_; }
  // The most bytes a zip upload may unpack to (the server's upload limit).
  void set_max_upload_bytes(std::size_t n) { max_upload_bytes_ = n; }
  // Uploads are read by reader.program in a child process (the server's
  // set-up); without one, in this process.  Removes what earlier runs left
  // in reader.temp_dir.
  void set_reader(const UploadReader& reader);
  // Where uploads are read (an empty program: in this process).
  const UploadReader& reader() const { return reader_; }
  void set_preview(const PreviewConfig& c) { preview_ = c; }
  const PreviewConfig& preview_config() const { return preview_; }
  std::uint64_t previews_computed() const { return previews_computed_; }
  std::uint64_t encodings_computed() const { return encodings_computed_; }

 private:
  // The cached encoding under `key`, computed once by `make` (concurrent
  // requests share one computation; least recently used dropped first).
  std::shared_ptr<const EncodedMesh> cached(const std::string& key,
                                            const std::function<std::shared_ptr<const EncodedMesh>()>& make);

  Store& store_;
  std::mutex mutex_;
  // Draco encodings by (sha256, bits), least recently used first.
  struct CacheEntry {
    std::shared_future<std::shared_ptr<const EncodedMesh>> value;
    std::size_t bytes = 0;
  };
  std::map<std::string, CacheEntry> encodings_;
  std::list<std::string> lru_;
  std::size_t cache_bytes_, used_bytes_ = 0;
  std::list<std::pair<std::string, std::shared_ptr<const Mesh>>> meshes_;  // by sha256, newest first
  std::uint64_t encodings_computed_ = 0;
  std::size_t max_upload_bytes_ = std::size_t(256) << 20;
  PreviewConfig preview_;
  std::uint64_t previews_computed_ = 0;
  UploadReader reader_;
};

// The JSON shapes of a stored mesh are the protocol's (protocol/mesh_json.h).
using protocol::material_of;
using protocol::mesh_json;
using protocol::mesh_json_text;

}  // namespace cgview::server
