// .raw: the values, x fastest, and a sidecar PATH.json (e.raw -> e.raw.json)
// giving dims, origin, voxel_size and type.
#include <nlohmann/json.hpp>

#include "io/mesh_io.h"
#include "io/parse_json.h"
#include "voxel/voxel_file_parts.h"

namespace cgview::voxel_file {

void write_raw_voxels(const VoxelGrid& g, const std::filesystem::path& path) {
  const auto d = g.dims();
  const Vec3 o = g.origin();
  nlohmann::json j = {{"format", "cgview-raw-voxels"},
                      {"version", 1},
                      {"data_file", path.filename().string()},
                      {"dims", {d[0], d[1], d[2]}},
                      {"origin", {o.x, o.y, o.z}},
                      {"voxel_size", g.voxel_size()},
                      {"type", g.type() == VoxelType::bit     ? "bit"
                               : g.type() == VoxelType::uint8 ? "uint8"
                                                              : "float32"},
                      {"bytes_per_voxel", g.type() == VoxelType::float32 ? 4 : 1},
                      {"order", "x fastest, then y, then z"},
                      {"endian", "little"},
                      {"origin_is", "the corner of voxel (0, 0, 0)"}};
  write_file_bytes(path, payload(g));
  write_file_bytes(path.string() + ".json", j.dump(2) + "\n");
}

VoxelGrid read_raw_voxels(const std::filesystem::path& path) {
  const std::string name = path.string();
  const std::string side = read_file_bytes(path.string() + ".json", 1 << 20);
  nlohmann::json j;
  try {
    j = parse_json(side, name + ".json");
    const auto d = checked_dims(j.at("dims").at(0).get<long long>(), j.at("dims").at(1).get<long long>(),
                                j.at("dims").at(2).get<long long>(), name + ".json");
    const std::string type = j.at("type").get<std::string>();
    const VoxelType t = type == "bit"       ? VoxelType::bit
                        : type == "uint8"   ? VoxelType::uint8
                        : type == "float32" ? VoxelType::float32
                                            : throw ParseError(name + ".json", "unknown type '" + type + "'",
                                                               std::nullopt, std::nullopt);
    const Vec3 o{j.at("origin").at(0).get<double>(), j.at("origin").at(1).get<double>(),
                 j.at("origin").at(2).get<double>()};
    const std::string data = read_file_bytes(path, kMaxRead);
    VoxelGrid g = make_grid(d, o, j.at("voxel_size").get<double>(), t, name, data.size());
    fill(g, data.data(), data.size(), name, 0);
    return g;
  } catch (const nlohmann::json::exception& ex) {
    bad(name + ".json", std::string("a malformed sidecar: ") + ex.what());
  }
}

}  // namespace cgview::voxel_file
