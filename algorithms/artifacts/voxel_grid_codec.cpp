// A voxel grid artifact: stored as NRRD (binary, and read back by every
// tool that reads grids); exported in the voxel formats of voxel/voxel_io.h
// and as legacy VTK (ASCII STRUCTURED_POINTS, for ParaView).
#include <unistd.h>

#include <atomic>
#include <charconv>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "artifacts/artifact_codec.h"
#include "core/errors.h"
#include "io/mesh_io.h"
#include "voxel/voxel_io.h"

namespace cgview {

namespace fs = std::filesystem;

namespace {

std::string legacy_vtk(const VoxelGrid& g, const std::string& name) {
  const auto d = g.dims();
  const Vec3 o = g.origin();
  const double h = g.voxel_size();
  char head[512];
  std::snprintf(head, sizeof head,
                "# vtk DataFile Version 3.0\n%s\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS %d %d %d\n"
                "ORIGIN %.17g %.17g %.17g\nSPACING %.17g %.17g %.17g\nPOINT_DATA %zu\nSCALARS %s float "
                "1\nLOOKUP_TABLE default\n",
                name.c_str(), d[0], d[1], d[2], o.x + h / 2, o.y + h / 2, o.z + h / 2, h, h, h, g.size(), "value");
  std::string out = head;
  char buf[32];
  for (std::size_t n = 0; n < g.size(); ++n) {
    const auto [p, ec] = std::to_chars(buf, buf + sizeof buf, double(g.get(g.unlinear(n))));
    out.append(buf, std::size_t(p - buf));
    out += '\n';
  }
  return out;
}

// Formats that OpenVDB or a sidecar keep in files: through a temporary one.
struct TempFile {
  explicit TempFile(const std::string& extension) {
    static std::atomic<unsigned> next{0};
    path = fs::temp_directory_path() /
           ("cgview-grid-" + std::to_string(::getpid()) + "-" + std::to_string(next++) + extension);
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path, ec);
    fs::remove(path.string() + ".json", ec);
  }
  fs::path path;
};

class VoxelGridCodec final : public ArtifactCodec {
 public:
  OutputKind kind() const override { return OutputKind::voxel_grid; }
  const std::vector<ArtifactFormat>& formats() const override {
    static const std::vector<ArtifactFormat> f = {
        {"nrrd", ".nrrd", "application/octet-stream"},     {"binvox", ".binvox", "application/octet-stream"},
        {"vti", ".vti", "application/octet-stream"},       {"vox", ".vox", "application/octet-stream"},
        {"vdb", ".vdb", "application/octet-stream"},       {"vtk", ".vtk", "text/plain; charset=utf-8"},
        {"raw", ".raw", "application/octet-stream", false}};
    return f;
  }

  std::string encode(const ArtifactValue& value, const std::string& name, const Mesh&,
                     const ArtifactFormat& format) const override {
    const VoxelGrid& g = std::get<VoxelGrid>(value);
    if (format.name == "nrrd") return encode_nrrd(g);
    if (format.name == "binvox") return encode_binvox(g);
    if (format.name == "vti") return encode_vti(g);
    if (format.name == "vox") return encode_vox(g);
    if (format.name == "vtk") return legacy_vtk(g, name);
    if (format.name == "vdb") {
      TempFile tmp(".vdb");
      write_vdb(g, tmp.path);
      return read_file_bytes(tmp.path, ~std::uint64_t(0));
    }
    throw UnsupportedFormat("a voxel grid as '" + format.name + "' is two files: write it to a path");
  }

  ArtifactValue decode(std::string_view stored, const std::string& name, const nlohmann::json& entry) const override {
    const std::string file = entry.value("file", name + ".nrrd");
    const std::string ext = fs::path(file).extension().string();
    const std::string bytes(stored);
    if (ext == ".nrrd") return decode_nrrd(bytes, file);
    if (ext == ".binvox") return decode_binvox(bytes, file);
    if (ext == ".vti") return decode_vti(bytes, file);
    if (ext == ".vox") return decode_vox(bytes, file);
    throw UnsupportedFormat("a stored voxel grid is nrrd, binvox, vti or vox, not '" + file + "'");
  }

  // Any format voxel_io reads, from its file (.vdb through OpenVDB, .raw with its .json).
  ArtifactValue load(const fs::path& dir, const nlohmann::json& entry) const override {
    return read_voxel_grid(dir / entry.value("file", ""));
  }

  void write(const Artifact& a, const Mesh& input, const fs::path& path) const override {
    const ArtifactFormat& f = format_of_path(path);
    if (f.name == "vtk") return ArtifactCodec::write(a, input, path);
    write_voxel_grid(std::get<VoxelGrid>(a.value), path);
  }
};

}  // namespace

const ArtifactCodec& voxel_grid_codec() {
  static const VoxelGridCodec codec;
  return codec;
}

}  // namespace cgview
