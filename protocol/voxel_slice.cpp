#include "voxel_slice.h"

#include <zlib.h>

#include <cstring>

#include "core/errors.h"

namespace cgview::protocol {
namespace {

template <class T>
void put(std::string& s, std::size_t at, T v) {
  std::memcpy(s.data() + at, &v, sizeof v);
}
template <class T>
T get(std::string_view s, std::size_t at) {
  T v;
  std::memcpy(&v, s.data() + at, sizeof v);
  return v;
}

}  // namespace

std::string encode_slice_payload(const VoxelGrid& grid, const VoxelSlice& slice) {
  const bool floats = grid.type() == VoxelType::float32;
  std::string raw;
  if (floats) {
    raw.resize(slice.values.size() * sizeof(float));
    std::memcpy(raw.data(), slice.values.data(), raw.size());
  } else {
    raw.resize(slice.values.size());
    for (std::size_t i = 0; i < raw.size(); ++i) raw[i] = char(std::uint8_t(slice.values[i]));
  }
  uLongf packed_size = compressBound(uLong(raw.size()));
  std::string out(kSliceHeaderBytes + packed_size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data() + kSliceHeaderBytes), &packed_size,
                reinterpret_cast<const Bytef*>(raw.data()), uLong(raw.size()), 6) != Z_OK)
    throw Error("zlib could not compress a slice");
  out.resize(kSliceHeaderBytes + packed_size);
  std::memcpy(out.data(), "CGVS", 4);
  put<std::uint16_t>(out, 4, 1);
  put<std::uint8_t>(out, 6, std::uint8_t(slice.axis));
  put<std::uint8_t>(out, 7, floats ? 2 : 1);
  put<std::uint32_t>(out, 8, std::uint32_t(slice.index));
  put<std::uint32_t>(out, 12, std::uint32_t(slice.width));
  put<std::uint32_t>(out, 16, std::uint32_t(slice.height));
  put<std::uint32_t>(out, 20, 1);
  put<std::uint32_t>(out, 24, std::uint32_t(raw.size()));
  put<std::uint32_t>(out, 28, std::uint32_t(packed_size));
  const double s = grid.voxel_size();
  Vec3 corner = grid.origin();
  corner[slice.axis] += slice.index * s;
  put<double>(out, 32, s);
  put<double>(out, 40, corner.x);
  put<double>(out, 48, corner.y);
  put<double>(out, 56, corner.z);
  return out;
}

DecodedSlice decode_slice_payload(std::string_view p) {
  if (p.size() < kSliceHeaderBytes || p.substr(0, 4) != "CGVS") throw InvalidInput("not a voxel slice payload");
  if (get<std::uint16_t>(p, 4) != 1) throw InvalidInput("voxel slice payload version is not 1");
  DecodedSlice d;
  d.slice.axis = get<std::uint8_t>(p, 6);
  const std::uint8_t type = get<std::uint8_t>(p, 7);
  if (d.slice.axis > 2 || (type != 1 && type != 2)) throw InvalidInput("bad axis or value type in a voxel slice");
  d.floats = type == 2;
  d.slice.index = int(get<std::uint32_t>(p, 8));
  d.slice.width = int(get<std::uint32_t>(p, 12));
  d.slice.height = int(get<std::uint32_t>(p, 16));
  const std::uint32_t raw = get<std::uint32_t>(p, 24), packed = get<std::uint32_t>(p, 28);
  const std::uint64_t n = std::uint64_t(d.slice.width) * std::uint64_t(d.slice.height);
  if (get<std::uint32_t>(p, 20) != 1 || raw != n * (d.floats ? 4 : 1) || packed != p.size() - kSliceHeaderBytes)
    throw InvalidInput("inconsistent sizes in a voxel slice header");
  d.voxel_size = get<double>(p, 32);
  d.corner = {get<double>(p, 40), get<double>(p, 48), get<double>(p, 56)};
  std::string bytes(raw, '\0');
  uLongf got = raw;
  if (uncompress(reinterpret_cast<Bytef*>(bytes.data()), &got,
                 reinterpret_cast<const Bytef*>(p.data() + kSliceHeaderBytes), packed) != Z_OK ||
      got != raw)
    throw InvalidInput("the voxel slice's zlib data is corrupt");
  d.slice.values.resize(n);
  if (d.floats) std::memcpy(d.slice.values.data(), bytes.data(), raw);
  else
    for (std::size_t i = 0; i < n; ++i) d.slice.values[i] = float(std::uint8_t(bytes[i]));
  return d;
}

}  // namespace cgview::protocol
