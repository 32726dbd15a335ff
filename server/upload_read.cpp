#include "upload_read.h"

#include "jobs/job_files.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <new>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sys/wait.h>

#include "child_process.h"
#include "core/ascii.h"
#include "core/errors.h"
#include "core/mesh_report.h"
#include "io/materials.h"
#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "mesh_report_json.h"
#include "io/zip_bundle.h"

namespace cgview::server {

namespace fs = std::filesystem;

namespace {

// A file's or an entry's name quoted in a warning or a material is the
// upload's bytes: invalid UTF-8 in it is replaced, not a reason to refuse
// the upload (or to write nothing).
std::string dump_replacing_invalid(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}
// The uploaded file that a mesh or MTL names, matched by base name without
// case (files written on Windows name ".\\Tex.JPG" for "tex.jpg").
const BundleFile* find_file(const std::vector<BundleFile>& files, const std::string& referenced) {
  const std::string want = ascii_lower(file_base_name(referenced));
  for (const auto& f : files)
    if (ascii_lower(file_base_name(f.name)) == want) return &f;
  return nullptr;
}

struct Textures {
  nlohmann::json material = nlohmann::json::object();  // has_uvs, textures, kd, materials
  std::vector<std::string> blobs;                      // one per material["textures"] entry
  std::set<const BundleFile*> used;                    // the upload's files a material or the mesh took
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
  t.used.insert(f);
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

// The upload's files of one kind (MTL libraries, PNG or JPEG images).
std::vector<const BundleFile*> files_that_are(const std::vector<BundleFile>& files, bool images) {
  std::vector<const BundleFile*> out;
  for (const auto& f : files)
    if (images ? !image_mime_type(f.bytes).empty() : ascii_lower(f.name).ends_with(".mtl")) out.push_back(&f);
  return out;
}

// An OBJ's materials: `materials` lists those its faces use in order of
// first use (the order of the material ids in its Draco stream), each with
// its Kd and the index of its texture in `textures`, or null.  An OBJ that
// names no library or no material, uploaded with exactly one, gets that one
// (said in a warning); with several or none, the warning says what it shows.
void find_obj_textures(Textures& t, const ReadResult& r, std::string_view mesh_bytes,
                       const std::vector<BundleFile>& files, bool bundle, std::vector<std::string>& warnings) {
  const ObjMaterialUse use = obj_material_use(mesh_bytes);
  std::vector<Material> mtl;
  for (const auto& lib : use.libraries) {
    if (const BundleFile* f = find_file(files, lib)) {
      t.used.insert(f);
      for (auto& m : parse_mtl(f->bytes)) mtl.push_back(std::move(m));
    } else {
      warnings.push_back(bundle ? "the material library '" + lib + "' is not in the zip: the mesh shows untextured"
                                : "the OBJ names the material library '" + lib +
                                      "': upload a zip of the OBJ, the MTL and its images to see its textures");
    }
  }
  if (use.libraries.empty()) {
    const auto libraries = files_that_are(files, false);
    if (libraries.size() == 1) {
      t.used.insert(libraries[0]);
      mtl = parse_mtl(libraries[0]->bytes);
      warnings.push_back("the OBJ names no material library (no mtllib line): the upload's only one, '" +
                         file_base_name(libraries[0]->name) + "', is used");
    } else if (libraries.size() > 1) {
      warnings.push_back("the OBJ names no material library (no mtllib line) and the upload holds " +
                         std::to_string(libraries.size()) + ": none is used (add an mtllib line to the OBJ)");
    }
  }
  if (use.face_material.size() != r.mesh.num_faces()) return;  // not the faces read_obj read: draw it plain
  // Textures in order of the faces they cover, so textures[0] is the main one.
  std::vector<std::size_t> order(use.names.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return use.faces.at(use.names[a]) > use.faces.at(use.names[b]);
  });
  std::vector<nlohmann::json> entries(use.names.size());
  for (const std::size_t i : order) {
    const std::string& name = use.names[i];
    const std::size_t faces = use.faces.at(name);
    const std::string n_faces = std::to_string(faces) + (faces == 1 ? " face" : " faces");
    auto m = std::find_if(mtl.begin(), mtl.end(), [&](const Material& x) { return x.name == name; });
    std::string image;
    if (m == mtl.end() && name.empty()) {
      // Faces before any usemtl line.
      const auto images = files_that_are(files, true);
      if (mtl.size() == 1) {
        m = mtl.begin();
        warnings.push_back(n_faces + " name no material (no usemtl line before them): the library's only one, '" +
                           m->name + "', is used for them");
      } else if (mtl.empty() && images.size() == 1 && r.mesh.has_uvs()) {
        image = images[0]->name;
        warnings.push_back("the OBJ names no material (no mtllib or usemtl line): the upload's only image, '" +
                           file_base_name(image) + "', is used as its texture");
      } else if (r.mesh.has_uvs()) {
        warnings.push_back(
            n_faces + " have texture coordinates but name no material (no usemtl line" +
            (use.libraries.empty() ? std::string(" and no mtllib line") : std::string()) +
            "): they show a checkerboard of their texture coordinates" +
            (images.size() > 1 || mtl.size() > 1 ? "; the upload holds several materials or images" : ""));
      }
    } else if (m == mtl.end() && !mtl.empty()) {
      warnings.push_back("the material '" + name + "' of " + n_faces +
                         " is in no material library uploaded: they show untextured");
    }
    nlohmann::json e = {{"name", name}, {"faces", faces}, {"kd", nullptr}, {"texture", nullptr}};
    if (m != mtl.end() && m->kd) e["kd"] = *m->kd;
    if (m != mtl.end() && !m->map_kd.empty()) image = m->map_kd;
    if (!image.empty())
      if (const auto tex = add_texture(t, r, files, bundle, image, warnings)) {
        e["texture"] = *tex;
        auto& te = t.material["textures"][*tex];
        if (!te.contains("material")) {
          te["material"] = m != mtl.end() ? m->name : name;
          if (m != mtl.end() && m->kd) te["kd"] = *m->kd;
        }
      }
    if (!t.material.contains("kd") && m != mtl.end() && m->kd) t.material["kd"] = *m->kd;
    entries[i] = std::move(e);
  }
  t.material["materials"] = entries;
}

// A glTF's materials as an OBJ's (materials in the order of the ids its
// faces carry, each with its base colour as kd and its texture), its images
// (the reader found them, embedded or among the upload's files) as textures.
void find_gltf_textures(Textures& t, const ReadResult& r, std::vector<std::string>& warnings) {
  std::vector<std::size_t> faces(r.materials.size(), 0);
  for (const std::uint32_t m : r.face_material)
    if (m < faces.size()) ++faces[m];
  std::vector<std::optional<std::size_t>> blob_of(r.textures.size());
  nlohmann::json entries = nlohmann::json::array();
  for (std::size_t i = 0; i < r.materials.size(); ++i) {
    const MeshMaterial& m = r.materials[i];
    nlohmann::json e = {{"name", m.name}, {"faces", faces[i]}, {"kd", nullptr}, {"texture", nullptr}};
    if (m.kd) e["kd"] = *m.kd;
    if (m.texture && *m.texture < r.textures.size()) {
      const MeshTexture& tex = r.textures[*m.texture];
      auto& blob = blob_of[*m.texture];
      if (!r.mesh.has_uvs()) {
        warnings.push_back("the mesh has no texture coordinates: its texture '" + tex.name + "' is not shown");
      } else {
        if (!blob) {
          nlohmann::json te = {{"name", tex.name},
                               {"mime", image_mime_type(tex.bytes)},
                               {"bytes", tex.bytes.size()},
                               {"material", m.name}};
          if (m.kd) te["kd"] = *m.kd;
          t.material["textures"].push_back(std::move(te));
          t.blobs.push_back(tex.bytes);
          blob = t.blobs.size() - 1;
        }
        e["texture"] = *blob;
      }
    }
    if (!t.material.contains("kd") && m.kd) t.material["kd"] = *m.kd;
    entries.push_back(std::move(e));
  }
  t.material["materials"] = std::move(entries);
}

// The textures and diffuse colours of a mesh from the files uploaded with
// it, and a warning listing those of its files nothing used.
Textures find_textures(const ReadResult& r, std::string_view mesh_bytes, const std::vector<BundleFile>& files,
                       const BundleFile* mesh_file, bool bundle, const std::set<const BundleFile*>& read_with,
                       std::vector<std::string>& warnings) {
  Textures t;
  t.used = read_with;
  t.material["has_uvs"] = r.mesh.has_uvs();
  t.material["textures"] = nlohmann::json::array();
  if (r.format == MeshFormat::obj) {
    find_obj_textures(t, r, mesh_bytes, files, bundle, warnings);
  } else if (r.format == MeshFormat::ply) {
    std::string image = ply_texture_file(mesh_bytes);
    const auto images = files_that_are(files, true);
    if (image.empty() && r.mesh.has_uvs()) {
      if (images.size() == 1) {
        image = images[0]->name;
        warnings.push_back("the PLY names no texture (no 'comment TextureFile' line): the upload's only image, '" +
                           file_base_name(image) + "', is used");
      } else {
        warnings.push_back(std::string("the PLY has texture coordinates but names no texture (no 'comment "
                                       "TextureFile' line): it shows a checkerboard of its texture coordinates") +
                           (images.size() > 1 ? "; the upload holds several images" : ""));
      }
    }
    if (!image.empty()) add_texture(t, r, files, bundle, image, warnings);
  } else if (r.format == MeshFormat::glb || r.format == MeshFormat::gltf) {
    find_gltf_textures(t, r, warnings);
  }
  std::string unused;
  for (const auto& f : files)
    if (&f != mesh_file && !t.used.count(&f)) unused += (unused.empty() ? "" : ", ") + f.name;
  if (!unused.empty()) warnings.push_back("files of the upload not used: " + unused);
  return t;
}

}  // namespace

std::string clean_upload_name(const std::string& name) {
  if (name.empty()) throw InvalidInput("the mesh needs a name (?name=FILE.EXT)");
  if (name.size() > 255) throw InvalidInput("the name is longer than 255 characters");
  for (unsigned char c : name)
    if (c < 32 || c == '/' || c == '\\' || c == 127)
      throw InvalidInput("the name may not hold '/', '\\' or control characters");
  return name;
}

UploadRead read_upload(const std::string& name, const std::string& format, std::string_view bytes,
                       std::size_t max_unpacked_bytes) {
  std::string n = clean_upload_name(name);
  const bool bundle = format == "zip" || (format.empty() && ascii_lower(n).ends_with(".zip"));
  std::vector<BundleFile> files;
  std::string_view mesh_bytes = bytes;
  const BundleFile* mesh_file = nullptr;
  if (bundle) {
    files = unzip_bundle(bytes, max_unpacked_bytes);
    mesh_file = &bundle_mesh_file(files);
    n = clean_upload_name(file_base_name(mesh_file->name));
    mesh_bytes = mesh_file->bytes;
  }
  const MeshFormat f = format_from_name(format.empty() || bundle ? n : "x." + format);
  // A glTF's buffers and images named by relative URIs: the zip's files
  // under the mesh file's directory, else one of the same base name.
  std::set<const BundleFile*> read_with;
  ReadOptions options;
  if (mesh_file) {
    const std::size_t slash = mesh_file->name.find_last_of('/');
    const std::string dir = slash == std::string::npos ? "" : mesh_file->name.substr(0, slash + 1);
    options.companion = [&](const std::string& path) -> std::optional<std::string_view> {
      const BundleFile* found = nullptr;
      for (const auto& file : files)
        if (&file != mesh_file && file.name == dir + path) found = &file;
      if (!found) found = find_file(files, path);
      if (!found || found == mesh_file) return std::nullopt;
      read_with.insert(found);
      return std::string_view(found->bytes);
    };
  }
  ReadResult r = read_mesh_bytes(mesh_bytes, f, n, options);
  if (r.mesh.num_vertices() == 0) throw InvalidInput(n + " is empty: it has no vertices and no faces");
  // A file of points and no faces is a point cloud, stored as a mesh with
  // no faces (core/point_cloud.h); its report and mesh JSON say "points".
  Textures textures = find_textures(r, mesh_bytes, files, mesh_file, bundle, read_with, r.warnings);
  UploadRead out;
  out.name = n;
  out.format = to_string(f);
  if (mesh_file) out.unpacked_mesh = mesh_file->bytes;
  // A glTF that needs the zip's other files is stored with them embedded: it reads alone.
  if (!r.self_contained.empty()) out.unpacked_mesh = std::move(r.self_contained);
  const MeshReport report = mesh_report(r.mesh);
  if (report.faces_inward)
    r.warnings.push_back(n +
                         ": the mesh is closed but its faces all face inward (a negative volume): shading looks "
                         "inside out; the SDF turns it outward for its run; Repair or Orient outward turns it");
  out.report_json = protocol::to_json(report).dump();
  out.warnings_json = dump_replacing_invalid(r.warnings);
  out.material_json = dump_replacing_invalid(textures.material);
  out.textures = std::move(textures.blobs);
  out.mesh = std::make_shared<const Mesh>(std::move(r.mesh));
  return out;
}

ReadDir::ReadDir(const fs::path& parent) {
  std::error_code ec;
  fs::create_directories(parent, ec);
  std::string t = (parent / "upload-XXXXXX").string();
  if (!::mkdtemp(t.data())) throw IoError("cannot make a directory in " + parent.string() + " to read the upload in");
  path_ = t;
}

ReadDir::~ReadDir() {
  std::error_code ec;
  fs::remove_all(path_, ec);
}

namespace {

// What a reader's exit says: nothing when it read the file, else what it
// refused it for, as the read would have thrown.
void reader_status(const UploadReader& reader, const std::string& name, const ReadDir& dir, std::optional<int> status) {
  // bubblewrap exits 128 + N for a child killed by signal N.
  if (status && WIFEXITED(*status) && WEXITSTATUS(*status) > 128 && reader.sandbox && reader.sandbox->enabled())
    status = WEXITSTATUS(*status) - 128;  // as a raw status: WIFSIGNALED, its signal in the low bits
  const std::string limit_mb = std::to_string(reader.memory_mb) + " MB";
  if (!status) {
    char secs[32];
    std::snprintf(secs, sizeof secs, "%g", double(reader.time_limit.count()) / 1000);
    throw TooLarge(name + ": reading it took longer than the server allows for one upload (" + std::string(secs) +
                   " s)");
  }
  if (WIFEXITED(*status) && WEXITSTATUS(*status) == 0) return;
  if (WIFEXITED(*status) && WEXITSTATUS(*status) == 2) {
    // A refusal whose error.json is missing still refuses the file (400), not the server (500).
    std::string text;
    try {
      text = child_file(dir, "error.json", 1 << 20);
    } catch (const std::exception&) {
    }
    // A reader that could not even write why it refused: a full disk, most likely.
    std::error_code ec;
    if (text.empty() && fs::space(dir.path(), ec).available < (1u << 20) && !ec)
      throw DiskFull(name + ": the server's storage is full");
    const nlohmann::json e = parse_json_or_discarded(text);
    const std::string kind = e.is_object() ? e.value("error", "") : "";
    const std::string detail = e.is_object() ? e.value("detail", "") : "";
    if (kind == "payload_too_large") throw TooLarge(detail);
    if (kind == "unsupported_format") throw UnsupportedFormat(detail);
    if (kind == "disk_full") throw DiskFull(detail);
    if (kind == "io_error") throw IoError(detail);
    throw InvalidInput(detail.empty() ? name + ": the file could not be read" : detail);
  }
  if (WIFEXITED(*status) && WEXITSTATUS(*status) == 3)
    throw TooLarge(name + ": reading it needs more memory than the server allows for one upload (" + limit_mb + ")");
  if (WIFEXITED(*status) && WEXITSTATUS(*status) == 127)
    throw IoError("cannot run the upload reader " + reader.program.string());
  if (WIFSIGNALED(*status))
    throw InvalidInput(name + ": the reader stopped with " + signal_name(WTERMSIG(*status)) +
                       " on this file (a malformed file it does not catch, or one that needs more than " + limit_mb +
                       "); nothing was stored");
  throw InvalidInput(name + ": the reader exited with status " + std::to_string(WEXITSTATUS(*status)) +
                     "; nothing was stored");
}

}  // namespace

std::string child_file(const ReadDir& dir, const std::string& name, std::uint64_t cap) {
  std::string why;
  const auto bytes = JobDir(dir.path()).read(name, cap, &why);
  if (!bytes) throw std::runtime_error(why.empty() ? name + " is missing" : why);
  return *bytes;
}

void run_reader_child(const UploadReader& reader, const char* mode, const std::string& name, const ReadDir& dir) {
  std::vector<std::string> argv = {reader.program.string(), mode, dir.path().string()};
  ChildOptions options;
  options.memory_mb = reader.memory_mb;
  options.stderr_file = dir.path() / "stderr.txt";
  options.end_with_server = true;
  options.clean_env = true;
  Sandbox::Slot slot;  // held until the reader is gone
  if (reader.sandbox && reader.sandbox->enabled()) {
    slot = reader.sandbox->take_slot();
    const std::string program = std::string(kSandboxPrograms) + "/" + reader.program.filename().string();
    Sandbox::Command c = reader.sandbox->wrap({program, mode, kSandboxJob},
                                              {.writable = dir.path(),
                                               .readable = {{reader.program, program}},
                                               .hidden = {reader.hidden},
                                               .visible = {reader.program.parent_path()}},
                                              slot.number(), options);
    argv = std::move(c.argv);
    options = std::move(c.options);
  }
  const pid_t pid = spawn_child(argv, options);
  if (pid < 0) throw IoError("cannot start a process to read the upload (fork failed)");
  reader_status(reader, name, dir, wait_child(pid, reader.time_limit));
}

int reader_main(const fs::path& dir, const std::function<void()>& read) {
  auto refuse = [&](const char* kind, const std::string& detail) {
    try {
      write_file_bytes(dir / "error.json", dump_replacing_invalid({{"error", kind}, {"detail", detail}}));
    } catch (const std::exception&) {
    }
    return 2;
  };
  end_with_server();
  try {
    read();
    return 0;
  } catch (const std::bad_alloc&) {
    return 3;
  } catch (const TooLarge& e) {
    return refuse("payload_too_large", e.what());
  } catch (const UnsupportedFormat& e) {
    return refuse("unsupported_format", e.what());
  } catch (const InvalidInput& e) {
    return refuse("invalid_mesh", e.what());
  } catch (const DiskFull& e) {
    return refuse("disk_full", e.what());
  } catch (const IoError& e) {
    return refuse("io_error", e.what());
  } catch (const std::length_error&) {
    return 3;  // a size past what a vector may hold: a claim no memory backs
  } catch (const std::exception& e) {
    return refuse("invalid_mesh", e.what());
  }
}

UploadRead read_upload_in_child(const UploadReader& reader, const std::string& name, const std::string& format,
                                std::string_view bytes, std::size_t max_unpacked_bytes) {
  const std::string n = clean_upload_name(name);  // named in the messages below
  ReadDir dir(reader.temp_dir);
  write_file_bytes(dir.path() / "upload", bytes);
  write_file_bytes(
      dir.path() / "request.json",
      nlohmann::json{{"name", name}, {"format", format}, {"max_unpacked_bytes", max_unpacked_bytes}}.dump());
  run_reader_child(reader, "--read-upload", n, dir);
  // What the child wrote is as untrusted as the upload: sizes capped, shape checked.
  const std::size_t cap = std::max<std::size_t>(bytes.size(), max_unpacked_bytes) + (std::size_t(1) << 20);
  UploadRead out;
  try {
    const nlohmann::json r = parse_json_or_discarded(child_file(dir, "result.json", std::size_t(64) << 20));
    if (!r.is_object()) throw std::runtime_error("not an object");
    out.name = clean_upload_name(r.at("name").get<std::string>());
    out.format = r.at("format").get<std::string>();
    out.report_json = r.at("report").dump();
    out.warnings_json = r.at("warnings").dump();
    out.material_json = r.at("material").dump();
    const std::size_t textures = r.at("textures").get<std::size_t>();
    if (textures > 1000) throw std::runtime_error("too many textures");
    for (std::size_t k = 0; k < textures; ++k)
      out.textures.push_back(child_file(dir, "texture-" + std::to_string(k), cap));
    // A glTF stored self-contained holds its files in base64: 4 bytes for 3.
    if (r.at("unpacked").get<bool>()) out.unpacked_mesh = child_file(dir, "mesh", cap / 3 * 4 + (std::size_t(1) << 20));
  } catch (const std::exception& e) {
    throw InvalidInput(n + ": the upload's reader gave an unreadable result (" + e.what() + ")");
  }
  return out;
}

int read_upload_main(const fs::path& dir) {
  return reader_main(dir, [&] {
    const nlohmann::json req = nlohmann::json::parse(read_file_bytes(dir / "request.json", 1 << 20));
    const std::string bytes = read_file_bytes(dir / "upload", std::numeric_limits<std::size_t>::max());
    const UploadRead r = read_upload(req.at("name").get<std::string>(), req.at("format").get<std::string>(), bytes,
                                     req.at("max_unpacked_bytes").get<std::size_t>());
    for (std::size_t k = 0; k < r.textures.size(); ++k)
      write_file_bytes(dir / ("texture-" + std::to_string(k)), r.textures[k]);
    if (!r.unpacked_mesh.empty()) write_file_bytes(dir / "mesh", r.unpacked_mesh);
    // result.json last (written through a rename): its presence means the rest is whole.
    write_file_bytes(dir / "result.json", nlohmann::json{{"name", r.name},
                                                         {"format", r.format},
                                                         {"report", nlohmann::json::parse(r.report_json)},
                                                         {"warnings", nlohmann::json::parse(r.warnings_json)},
                                                         {"material", nlohmann::json::parse(r.material_json)},
                                                         {"textures", r.textures.size()},
                                                         {"unpacked", !r.unpacked_mesh.empty()}}
                                              .dump());
  });
}

}  // namespace cgview::server
