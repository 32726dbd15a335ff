// The payload of a voxel-slice frame (FrameKind::voxel_slice, API.md): a
// 64-byte little-endian header, then the slice's values compressed with zlib.
//
//   0  "CGVS"            4  u16 version (1)   6  u8 axis (0 x, 1 y, 2 z)
//   7  u8 value type (1 = uint8, 2 = float32)
//   8  u32 index         12 u32 width         16 u32 height
//   20 u32 compression (1 = zlib)             24 u32 raw bytes   28 u32 compressed bytes
//   32 f64 voxel size    40 f64 x, 48 f64 y, 56 f64 z: the world corner of the
//                        slice's first voxel (its lowest corner)
// Values row by row, the first of the two other axes fastest (z slice: x
// then y; x slice: y then z; y slice: x then z), as voxel/voxel_ops.h's slice().
#pragma once

#include <string>
#include <string_view>

#include "core/voxel_grid.h"
#include "voxel/voxel_ops.h"

namespace cgview::protocol {

constexpr std::uint32_t kSliceHeaderBytes = 64;

// The payload of the slice of `grid` (bit and uint8 grids as uint8, float as float32).
std::string encode_slice_payload(const VoxelGrid& grid, const VoxelSlice& slice);

struct DecodedSlice {
  VoxelSlice slice;
  bool floats = false;  // the value type on the wire
  double voxel_size = 0;
  Vec3 corner{};
};
// Parses and inflates a payload; throws InvalidInput for a malformed one.
DecodedSlice decode_slice_payload(std::string_view payload);

}  // namespace cgview::protocol
