#include "mesh_service.h"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "core/cluster_decimate.h"
#include "core/errors.h"
#include "stored_order.h"
#include "io/draco_io.h"
#include "io/materials.h"
#include "io/mesh_io.h"
#include "upload_read.h"

namespace cgview::server {

namespace {
constexpr std::size_t kMeshesKept = 8;

// Each face's index into the stored mesh's `materials`, when its faces use
// more than one (an OBJ's usemtl groups, a glTF's primitives' materials);
// empty otherwise.  It depends on the
// mesh file's bytes only, so encodings stay keyed by the file's sha256.
std::vector<std::uint32_t> face_materials(Store& store, const MeshRecord& rec, std::size_t faces) {
  if (rec.format == "glb" || rec.format == "gltf") {
    ReadResult r = read_mesh_bytes(store.read_blob(rec), format_from_name("x." + rec.format), rec.name);
    if (r.materials.size() < 2 || r.face_material.size() != faces) return {};
    return std::move(r.face_material);
  }
  if (rec.format != "obj") return {};
  ObjMaterialUse use = obj_material_use(store.read_blob(rec));
  if (use.names.size() < 2 || use.face_material.size() != faces) return {};
  return std::move(use.face_material);
}
}  // namespace

MeshService::MeshService(Store& store, std::size_t cache_bytes) : store_(store), cache_bytes_(cache_bytes) {}

MeshRecord MeshService::upload(const std::string& name, const std::string& format, std::string_view bytes,
                               const std::string& owner) {
  UploadRead r = reader_.program.empty() ? read_upload(name, format, bytes, max_upload_bytes_)
                                         : read_upload_in_child(reader_, name, format, bytes, max_upload_bytes_);
  const std::string_view mesh_bytes = r.unpacked_mesh.empty() ? bytes : std::string_view(r.unpacked_mesh);
  MeshRecord rec;
  rec.name = r.name;
  rec.format = r.format;
  rec.sha256 = sha256_hex(mesh_bytes);
  rec.report_json = std::move(r.report_json);
  rec.warnings_json = std::move(r.warnings_json);
  rec.material_json = std::move(r.material_json);
  rec.owner = owner;
  rec = store_.add_mesh(std::move(rec), mesh_bytes, r.textures);
  if (r.mesh) {
    std::lock_guard lock(mutex_);
    meshes_.emplace_front(rec.sha256, std::move(r.mesh));
    if (meshes_.size() > kMeshesKept) meshes_.pop_back();
  }
  return rec;
}

void MeshService::set_reader(const UploadReader& reader) {
  reader_ = reader;
  if (reader_.program.empty()) return;
  // What a killed server left of uploads being read.
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(reader_.temp_dir, ec))
    if (e.path().filename().string().starts_with("upload-")) std::filesystem::remove_all(e.path(), ec);
}

std::shared_ptr<const Mesh> MeshService::mesh(const MeshRecord& rec) {
  {
    std::lock_guard lock(mutex_);
    for (auto it = meshes_.begin(); it != meshes_.end(); ++it)
      if (it->first == rec.sha256) {
        meshes_.splice(meshes_.begin(), meshes_, it);
        return it->second;
      }
  }
  const std::string bytes = store_.read_blob(rec);
  auto m = std::make_shared<const Mesh>(read_mesh_bytes(bytes, format_from_name("x." + rec.format), rec.name).mesh);
  std::lock_guard lock(mutex_);
  meshes_.emplace_front(rec.sha256, m);
  if (meshes_.size() > kMeshesKept) meshes_.pop_back();
  return m;
}

std::shared_ptr<const EncodedMesh> MeshService::cached(
    const std::string& key, const std::function<std::shared_ptr<const EncodedMesh>()>& make) {
  std::promise<std::shared_ptr<const EncodedMesh>> promise;
  std::shared_future<std::shared_ptr<const EncodedMesh>> pending;
  {
    std::lock_guard lock(mutex_);
    if (auto it = encodings_.find(key); it != encodings_.end()) {
      lru_.remove(key);
      lru_.push_back(key);
      pending = it->second.value;
    } else {
      encodings_[key].value = promise.get_future().share();
      lru_.push_back(key);
    }
  }
  if (pending.valid()) return pending.get();  // cached, or being computed by another request
  try {
    std::shared_ptr<const EncodedMesh> result = make();
    promise.set_value(result);
    std::lock_guard lock(mutex_);
    encodings_[key].bytes = result->bytes.size();
    used_bytes_ += result->bytes.size();
    while (used_bytes_ > cache_bytes_ && lru_.size() > 1) {
      const std::string victim = lru_.front();
      lru_.pop_front();
      used_bytes_ -= encodings_[victim].bytes;
      encodings_.erase(victim);
    }
    return result;
  } catch (...) {
    promise.set_exception(std::current_exception());
    std::lock_guard lock(mutex_);
    encodings_.erase(key);
    lru_.remove(key);
    throw;
  }
}

namespace {
// How the streams are written: stored_order() writes the mesh again with these.
WriteOptions stream_options(int bits) {
  WriteOptions wo;
  wo.position_bits = bits;
  return wo;
}

std::shared_ptr<const EncodedMesh> encode(const Mesh& m, int bits, std::span<const std::uint32_t> face_material = {}) {
  auto enc = std::make_shared<EncodedMesh>();
  enc->bytes = write_draco_with_materials(m, face_material, stream_options(bits));
  enc->vertices = m.num_vertices();
  enc->faces = m.num_faces();
  enc->has_normals = m.has_normals();
  enc->has_colors = m.has_colors();
  return enc;
}
}  // namespace

void check_quantization_bits(int bits) {
  if (bits < 1 || bits > 30) throw InvalidInput("quantization must be 1..30 bits, got " + std::to_string(bits));
}

std::shared_ptr<const EncodedMesh> MeshService::draco(const MeshRecord& rec, int bits) {
  check_quantization_bits(bits);
  return cached(rec.sha256 + "/" + std::to_string(bits), [&] {
    const std::shared_ptr<const Mesh> m = mesh(rec);
    auto enc = encode(*m, bits, face_materials(store_, rec, m->num_faces()));
    std::lock_guard lock(mutex_);
    ++encodings_computed_;
    return enc;
  });
}

std::string MeshService::stored_order(const MeshRecord& rec, int bits) {
  const std::shared_ptr<const EncodedMesh> enc = draco(rec, bits);
  std::call_once(enc->stored_order_once, [&] {
    const std::shared_ptr<const Mesh> m = mesh(rec);
    const DracoStoredOrder order =
        draco_stored_order(enc->bytes, *m, face_materials(store_, rec, m->num_faces()), stream_options(bits));
    enc->stored_order = protocol::pack_stored_order(order.points, order.faces);
  });
  return enc->stored_order;
}

bool MeshService::has_preview(const MeshRecord& rec) const {
  if (preview_.threshold_faces == 0) return false;
  const nlohmann::json report = nlohmann::json::parse(rec.report_json, nullptr, false);
  const nlohmann::json faces = report.is_object() ? report.value("faces", nlohmann::json()) : nlohmann::json();
  return faces.is_number_unsigned() && faces.get<std::uint64_t>() > preview_.threshold_faces;
}

std::shared_ptr<const EncodedMesh> MeshService::preview(const MeshRecord& rec) {
  if (!has_preview(rec))
    throw InvalidInput("mesh " + rec.id + " has no preview (it has at most " +
                       std::to_string(preview_.threshold_faces) + " faces)");
  // Keyed by the mesh id too: the blob belongs to one stored mesh.
  return cached(rec.sha256 + "/preview/" + rec.id, [&]() -> std::shared_ptr<const EncodedMesh> {
    if (std::optional<std::string> bytes = store_.read_preview(rec)) {
      try {
        const Mesh m = read_mesh_bytes(*bytes, MeshFormat::drc, rec.id + ".preview.drc").mesh;
        auto enc = std::make_shared<EncodedMesh>();
        enc->bytes = std::move(*bytes);
        enc->vertices = m.num_vertices();
        enc->faces = m.num_faces();
        enc->has_colors = m.has_colors();
        return enc;
      } catch (const std::exception&) {
        // A damaged blob: make it again.
      }
    }
    auto enc = encode(cluster_decimate(*mesh(rec), {preview_.target_faces}).mesh, 14);
    store_.write_preview(rec, enc->bytes);
    std::lock_guard lock(mutex_);
    ++previews_computed_;
    return enc;
  });
}

std::string MeshService::download(const MeshRecord& rec, const std::string& format) {
  const MeshFormat f = format_from_name("x." + format);
  if (!can_write(f)) throw UnsupportedFormat("cannot write " + format + " (writable: " + writable_formats() + ")");
  if (format == rec.format) return store_.read_blob(rec);
  if (f == MeshFormat::drc) return draco(rec, 14)->bytes;
  return write_mesh_bytes(*mesh(rec), f);
}

int MeshService::import_samples(const std::vector<std::filesystem::path>& files, std::size_t max_bytes_each) {
  int added = 0;
  for (const auto& p : files) {
    try {
      const std::string bytes = read_file_bytes(p, max_bytes_each);
      if (store_.find_by_sha256(sha256_hex(bytes), kSystemOwner)) continue;
      const MeshRecord rec = upload(p.filename().string(), "", bytes, kSystemOwner);
      store_.set_shared("mesh", rec.id, {kEveryone}, true);
      ++added;
    } catch (const std::exception&) {
      // Not a mesh we read (or too large): samples are a convenience.
    }
  }
  return added;
}

}  // namespace cgview::server
