#include "registry/artifact_io.h"

#include <charconv>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/skeleton_io.h"
#include "voxel/voxel_io.h"

namespace cgview {

namespace {

std::string ext_of(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

void append_number(std::string& s, double v) {
  char buf[32];
  const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, v);
  s.append(buf, std::size_t(p - buf));
}

// Through nlohmann so that names are escaped and a NaN or infinity, which
// JSON cannot hold, becomes null.
std::string metrics_json(const Metrics& m) { return nlohmann::json(m).dump() + "\n"; }

[[noreturn]] void unsupported(const char* kind, const std::string& ext, const char* known) {
  throw UnsupportedFormat(std::string("a ") + kind + " cannot be saved as '" + ext + "' (use " + known + ")");
}

}  // namespace

std::string default_extension(const Artifact& a) {
  // By type, not by index: the variant may grow in another order.
  if (std::holds_alternative<Text>(a.value)) return ".txt";
  if (std::holds_alternative<Animation>(a.value)) return ".frames";
  switch (a.value.index()) {
    case 0:
      return ".ply";
    case 1:
      return ".txt";
    case 2:
      return ".nrrd";  // binary and read back by read_voxel_grid (ASCII .vtk is 20x larger)
    case 3:
      return ".obj";
    default:
      return ".json";
  }
}

void check_artifact_extension(OutputKind kind, const std::filesystem::path& path) {
  const std::string ext = ext_of(path);
  switch (kind) {
    case OutputKind::mesh:
      if (!can_write(format_from_name(path.string())))
        throw UnsupportedFormat("a mesh cannot be saved as '" + ext + "' (use " + writable_formats() + ")");
      return;
    case OutputKind::scalar_field:
      if (ext != ".txt" && ext != ".csv" && ext != ".ply") unsupported("scalar field", ext, ".txt, .csv or .ply");
      return;
    case OutputKind::voxel_grid:
      if (ext != ".vtk" && !is_voxel_format(path))
        unsupported("voxel grid", ext, ".vtk, .binvox, .raw, .nrrd, .vti, .vox or .vdb");
      return;
    case OutputKind::skeleton:
      skeleton_format_from_name(path.filename().string());  // throws UnsupportedFormat naming the formats
      return;
    case OutputKind::metrics:
      if (ext != ".json") unsupported("metrics table", ext, ".json");
      return;
    case OutputKind::text:
      if (ext != ".txt" && ext != ".bin") unsupported("text", ext, ".txt or .bin");
      return;
    case OutputKind::animation:
      if (ext != ".frames") unsupported("animation", ext, ".frames");
      return;
  }
}

void write_artifact(const Artifact& a, const Mesh& input, const std::filesystem::path& path) {
  const std::string ext = ext_of(path);
  std::string out;
  if (const auto* mesh = std::get_if<Mesh>(&a.value)) {
    write_mesh(*mesh, path);
    return;
  } else if (const auto* f = std::get_if<ScalarField>(&a.value)) {
    if (ext == ".ply") {
      out = write_ply_with_field(input, *f);
    } else if (ext == ".txt" || ext == ".csv") {
      const bool csv = ext == ".csv";
      if (csv) out = std::string(to_string(f->location)) + "," + f->name + "\n";
      for (std::size_t i = 0; i < f->values.size(); ++i) {
        if (csv) out += std::to_string(i) + ",";
        append_number(out, f->values[i]);
        out += '\n';
      }
    } else {
      unsupported("scalar field", ext, ".txt, .csv or .ply");
    }
  } else if (const auto* g = std::get_if<VoxelGrid>(&a.value)) {
    if (is_voxel_format(path)) {
      write_voxel_grid(*g, path);
      return;
    }
    if (ext != ".vtk") unsupported("voxel grid", ext, ".vtk, .binvox, .raw, .nrrd, .vti, .vox or .vdb");
    const auto d = g->dims();
    const Vec3 o = g->origin();
    char head[512];
    std::snprintf(head, sizeof head,
                  "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS %d %d %d\n"
                  "ORIGIN %.17g %.17g %.17g\nSPACING %.17g %.17g %.17g\nPOINT_DATA %zu\nSCALARS %s float "
                  "1\nLOOKUP_TABLE default\n",
                  a.name.c_str(), d[0], d[1], d[2], o.x + g->voxel_size() / 2, o.y + g->voxel_size() / 2,
                  o.z + g->voxel_size() / 2, g->voxel_size(), g->voxel_size(), g->voxel_size(), g->size(), "value");
    out = head;
    for (std::size_t n = 0; n < g->size(); ++n) {
      append_number(out, g->get(g->unlinear(n)));
      out += '\n';
    }
  } else if (const auto* s = std::get_if<Skeleton>(&a.value)) {
    write_skeleton(*s, path);
    return;
  } else if (const auto* m = std::get_if<Metrics>(&a.value)) {
    if (ext != ".json") unsupported("metrics table", ext, ".json");
    out = metrics_json(*m);
  } else if (const auto* t = std::get_if<Text>(&a.value)) {
    if (ext != ".txt" && ext != ".bin") unsupported("text", ext, ".txt or .bin");
    out = t->bytes;  // as they are: a message's bytes need not be UTF-8
  } else if (const auto* anim = std::get_if<Animation>(&a.value)) {
    if (ext != ".frames") unsupported("animation", ext, ".frames");
    out = encode_frames(*anim);
  }
  write_file_bytes(path, out);
}

std::vector<std::string> InputFiles::read(const InputSpec& spec, const std::filesystem::path& path) {
  switch (spec.kind) {
    case OutputKind::voxel_grid:
      inputs_.add(spec.name, grids_.insert_or_assign(spec.name, read_voxel_grid(path)).first->second);
      return {};
    case OutputKind::skeleton:
      inputs_.add(spec.name, skeletons_.insert_or_assign(spec.name, read_skeleton(path)).first->second);
      return {};
    default: {
      ReadResult r = read_mesh_file(path);
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
