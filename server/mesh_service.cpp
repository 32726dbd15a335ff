#include "mesh_service.h"

#include <algorithm>
#include <cctype>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>

#include "core/cluster_decimate.h"
#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/draco_io.h"
#include "io/materials.h"
#include "io/mesh_io.h"
#include "mesh_report_json.h"
#include "zip_bundle.h"

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

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The uploaded file that a mesh or MTL names, matched by base name without
// case (files written on Windows name ".\\Tex.JPG" for "tex.jpg").
const BundleFile* find_file(const std::vector<BundleFile>& files, const std::string& referenced) {
  const std::string want = lower(file_base_name(referenced));
  for (const auto& f : files)
    if (lower(file_base_name(f.name)) == want) return &f;
  return nullptr;
}

// The one mesh file among a zip's files.
const BundleFile& mesh_file_of(const std::vector<BundleFile>& files) {
  std::vector<const BundleFile*> meshes;
  for (const auto& f : files) {
    try {
      if (can_read(format_from_name(f.name))) meshes.push_back(&f);
    } catch (const UnsupportedFormat&) {
      // an MTL, an image, a readme
    }
  }
  if (meshes.empty()) throw InvalidInput("the zip holds no mesh file (readable: " + readable_formats() + ")");
  if (meshes.size() > 1)
    throw InvalidInput("the zip holds several mesh files ('" + meshes[0]->name + "', '" + meshes[1]->name +
                       "', ...): upload one mesh per zip");
  return *meshes.front();
}

struct Textures {
  nlohmann::json material = nlohmann::json::object();  // has_uvs, textures, kd, materials
  std::vector<std::string> blobs;                      // one per material["textures"] entry
};

// The texture named `image` among the uploaded files as a textures[] entry
// and its blob, or a warning saying why it is not shown.
std::optional<std::size_t> add_texture(Textures& t, const ReadResult& r, const std::vector<BundleFile>& files,
                                       bool bundle, const std::string& image, std::vector<std::string>& warnings) {
  const BundleFile* f = find_file(files, image);
  if (!f) {
    warnings.push_back("the texture '" + image + "' is not in the upload: its faces show untextured" +
                       (bundle ? "" : " (upload a zip of the mesh and its images)"));
    return std::nullopt;
  }
  const std::string mime = image_mime_type(f->bytes);
  if (mime.empty()) {
    warnings.push_back("the texture '" + image + "' is not a PNG or JPEG image: its faces show untextured");
    return std::nullopt;
  }
  if (!r.mesh.has_uvs()) {
    warnings.push_back("the mesh has no texture coordinates: its texture '" + image + "' is not shown");
    return std::nullopt;
  }
  const std::string name = file_base_name(f->name);
  for (std::size_t i = 0; i < t.blobs.size(); ++i)
    if (t.material["textures"][i]["name"] == name) return i;  // two materials, one image: one blob
  t.material["textures"].push_back({{"name", name}, {"mime", mime}, {"bytes", f->bytes.size()}});
  t.blobs.push_back(f->bytes);
  return t.blobs.size() - 1;
}

// The textures and diffuse colours of a mesh from the files uploaded with it:
// for an OBJ, `materials` lists the materials its faces use in order of first
// use (the order of the material ids in its Draco stream), each with its Kd
// and the index of its texture in `textures`, or null.
Textures find_textures(const ReadResult& r, std::string_view mesh_bytes, const std::vector<BundleFile>& files,
                       bool bundle, std::vector<std::string>& warnings) {
  Textures t;
  t.material["has_uvs"] = r.mesh.has_uvs();
  t.material["textures"] = nlohmann::json::array();
  if (r.format == MeshFormat::obj) {
    const ObjMaterialUse use = obj_material_use(mesh_bytes);
    std::vector<Material> mtl;
    for (const auto& lib : use.libraries) {
      if (const BundleFile* f = find_file(files, lib)) {
        for (auto& m : parse_mtl(f->bytes)) mtl.push_back(std::move(m));
      } else {
        warnings.push_back(bundle ? "the material library '" + lib + "' is not in the zip: the mesh shows untextured"
                                  : "the OBJ names the material library '" + lib +
                                        "': upload a zip of the OBJ, the MTL and its images to see its textures");
      }
    }
    if (use.face_material.size() != r.mesh.num_faces()) return t;  // not the faces read_obj read: draw it plain
    // Textures in order of the faces they cover, so textures[0] is the main one.
    std::vector<std::size_t> order(use.names.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return use.faces.at(use.names[a]) > use.faces.at(use.names[b]); });
    std::vector<nlohmann::json> entries(use.names.size());
    for (const std::size_t i : order) {
      const std::string& name = use.names[i];
      const auto m = std::find_if(mtl.begin(), mtl.end(), [&](const Material& x) { return x.name == name; });
      nlohmann::json e = {{"name", name}, {"faces", use.faces.at(name)}, {"kd", nullptr}, {"texture", nullptr}};
      if (m != mtl.end() && m->kd) e["kd"] = *m->kd;
      if (m != mtl.end() && !m->map_kd.empty())
        if (const auto tex = add_texture(t, r, files, bundle, m->map_kd, warnings)) {
          e["texture"] = *tex;
          auto& te = t.material["textures"][*tex];
          if (!te.contains("material")) {
            te["material"] = name;
            if (m->kd) te["kd"] = *m->kd;
          }
        }
      if (!t.material.contains("kd") && m != mtl.end() && m->kd) t.material["kd"] = *m->kd;
      entries[i] = std::move(e);
    }
    t.material["materials"] = entries;
  } else if (r.format == MeshFormat::ply) {
    const std::string image = ply_texture_file(mesh_bytes);
    if (!image.empty()) add_texture(t, r, files, bundle, image, warnings);
  }
  return t;
}

// Each face's index into the stored mesh's `materials`, when its faces use
// more than one (an OBJ's usemtl groups); empty otherwise.  It depends on the
// mesh file's bytes only, so encodings stay keyed by the file's sha256.
std::vector<std::uint32_t> face_materials(Store& store, const MeshRecord& rec, std::size_t faces) {
  if (rec.format != "obj") return {};
  ObjMaterialUse use = obj_material_use(store.read_blob(rec));
  if (use.names.size() < 2 || use.face_material.size() != faces) return {};
  return std::move(use.face_material);
}
}  // namespace

MeshService::MeshService(Store& store, std::size_t cache_bytes) : store_(store), cache_bytes_(cache_bytes) {}

MeshRecord MeshService::upload(const std::string& name, const std::string& format, std::string_view bytes,
                               const std::string& owner) {
  std::string n = clean_name(name);
  const bool bundle = format == "zip" || (format.empty() && lower(n).ends_with(".zip"));
  std::vector<BundleFile> files;
  std::string_view mesh_bytes = bytes;
  if (bundle) {
    files = unzip_bundle(bytes, max_upload_bytes_);
    const BundleFile& m = mesh_file_of(files);
    n = clean_name(file_base_name(m.name));
    mesh_bytes = m.bytes;
  }
  const MeshFormat f = format_from_name(format.empty() || bundle ? n : "x." + format);
  ReadResult r = read_mesh_bytes(mesh_bytes, f, n);
  if (r.mesh.num_faces() == 0) throw InvalidInput(n + ": the mesh has no faces");
  Textures textures = find_textures(r, mesh_bytes, files, bundle, r.warnings);
  MeshRecord rec;
  rec.name = n;
  rec.format = to_string(f);
  rec.sha256 = sha256_hex(mesh_bytes);
  rec.report_json = protocol::to_json(mesh_report(r.mesh)).dump();
  rec.warnings_json = nlohmann::json(r.warnings).dump();
  rec.material_json = textures.material.dump();
  rec.owner = owner;
  rec = store_.add_mesh(std::move(rec), mesh_bytes, textures.blobs);
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

std::shared_ptr<const EncodedMesh> MeshService::cached(const std::string& key,
                                                      const std::function<std::shared_ptr<const EncodedMesh>()>& make) {
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
std::shared_ptr<const EncodedMesh> encode(const Mesh& m, int bits, std::span<const std::uint32_t> face_material = {}) {
  auto enc = std::make_shared<EncodedMesh>();
  WriteOptions wo;
  wo.position_bits = bits;
  enc->bytes = write_draco_with_materials(m, face_material, wo);
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

bool MeshService::has_preview(const MeshRecord& rec) const {
  if (preview_.threshold_faces == 0) return false;
  const nlohmann::json report = nlohmann::json::parse(rec.report_json, nullptr, false);
  const nlohmann::json faces = report.is_object() ? report.value("faces", nlohmann::json()) : nlohmann::json();
  return faces.is_number_unsigned() && faces.get<std::uint64_t>() > preview_.threshold_faces;
}

std::shared_ptr<const EncodedMesh> MeshService::preview(const MeshRecord& rec) {
  if (!has_preview(rec))
    throw InvalidInput("mesh " + rec.id + " has no preview (it has at most " + std::to_string(preview_.threshold_faces) +
                       " faces)");
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

nlohmann::json material_of(const MeshRecord& r) {
  nlohmann::json m = nlohmann::json::parse(r.material_json, nullptr, false);
  if (!m.is_object()) m = nlohmann::json::object();
  if (!m.contains("has_uvs")) m["has_uvs"] = false;
  if (!m.contains("textures")) m["textures"] = nlohmann::json::array();
  return m;
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
  j.update(material_of(r));
  return j;
}

std::string mesh_json_text(const MeshRecord& r) {
  std::string s = mesh_head(r).dump();
  s.pop_back();  // the closing brace
  std::string m = material_of(r).dump();  // {"has_uvs":...}: spliced in without its braces
  return s + ",\"report\":" + r.report_json + ",\"warnings\":" + r.warnings_json + "," + m.substr(1);
}

}  // namespace cgview::server
