#include "mesh_service.h"

#include <algorithm>
#include <nlohmann/json.hpp>

#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/mesh_io.h"
#include "mesh_report_json.h"

namespace cgview::server {

namespace {
constexpr std::size_t kMeshesKept = 8;

std::string clean_name(const std::string& name) {
  if (name.empty()) throw InvalidInput("the mesh needs a name (?name=FILE.EXT)");
  if (name.size() > 255) throw InvalidInput("the name is longer than 255 characters");
  for (unsigned char c : name)
    if (c < 32 || c == '/' || c == '\\' || c == 127) throw InvalidInput("the name may not hold '/', '\\' or control characters");
  return name;
}
}  // namespace

MeshService::MeshService(Store& store, std::size_t cache_bytes) : store_(store), cache_bytes_(cache_bytes) {}

MeshRecord MeshService::upload(const std::string& name, const std::string& format, std::string_view bytes,
                               const std::string& owner) {
  const std::string n = clean_name(name);
  const MeshFormat f = format_from_name(format.empty() ? n : "x." + format);
  ReadResult r = read_mesh_bytes(bytes, f, n);
  if (r.mesh.num_faces() == 0) throw InvalidInput(n + ": the mesh has no faces");
  MeshRecord rec;
  rec.name = n;
  rec.format = to_string(f);
  rec.sha256 = sha256_hex(bytes);
  rec.report_json = protocol::to_json(mesh_report(r.mesh)).dump();
  rec.warnings_json = nlohmann::json(r.warnings).dump();
  rec.owner = owner;
  rec = store_.add_mesh(std::move(rec), bytes);
  std::lock_guard lock(mutex_);
  meshes_.emplace_front(rec.sha256, std::make_shared<const Mesh>(std::move(r.mesh)));
  if (meshes_.size() > kMeshesKept) meshes_.pop_back();
  return rec;
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

std::shared_ptr<const EncodedMesh> MeshService::draco(const MeshRecord& rec, int bits) {
  if (bits < 1 || bits > 30) throw InvalidInput("quantization must be 1..30 bits, got " + std::to_string(bits));
  const std::string key = rec.sha256 + "/" + std::to_string(bits);
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
    auto m = mesh(rec);
    auto enc = std::make_shared<EncodedMesh>();
    WriteOptions wo;
    wo.position_bits = bits;
    enc->bytes = write_mesh_bytes(*m, MeshFormat::drc, wo);
    enc->vertices = m->num_vertices();
    enc->faces = m->num_faces();
    enc->has_normals = m->has_normals();
    enc->has_colors = m->has_colors();
    std::shared_ptr<const EncodedMesh> result = enc;
    promise.set_value(result);
    std::lock_guard lock(mutex_);
    ++encodings_computed_;
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

namespace {
nlohmann::json mesh_head(const MeshRecord& r) {
  return {{"id", r.id}, {"name", r.name}, {"format", r.format}, {"bytes", r.bytes}, {"created", r.created}, {"sha256", r.sha256},
          {"owner", r.owner}};
}
}  // namespace

nlohmann::json mesh_json(const MeshRecord& r) {
  nlohmann::json j = mesh_head(r);
  j["report"] = nlohmann::json::parse(r.report_json);
  j["warnings"] = nlohmann::json::parse(r.warnings_json);
  return j;
}

std::string mesh_json_text(const MeshRecord& r) {
  std::string s = mesh_head(r).dump();
  s.pop_back();  // the closing brace
  return s + ",\"report\":" + r.report_json + ",\"warnings\":" + r.warnings_json + "}";
}

}  // namespace cgview::server
