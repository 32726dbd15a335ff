// Curve skeleton files, read and written:
//   .polylines.txt  CGAL's polylines text ("N x1 y1 z1 ... xN yN zN" a line;
//                   what Mean_curvature_flow_skeletonization's examples write):
//                   points repeated exactly between lines are one node;
//   .cg             the curve-graph text of the mesh-contraction and
//                   mean-curvature-flow skeleton tools ("# D:3 NV:n NE:m",
//                   then "v x y z" lines, then "e i j" lines, 1-based);
//   .obj            "v x y z" and "l i j ..." records (1-based; negative
//                   indices count back), other records ignored;
//   .json           {"nodes": [[x, y, z], ...], "edges": [[i, j], ...],
//                   "radii": [r, ...] (optional)}, 0-based.
// A malformed file throws ParseError naming the file and the line; indices
// out of range, loops and non-finite positions are refused the same way.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "core/skeleton.h"

namespace cgview {

enum class SkeletonFormat { polylines, cg, obj, json };

// From the file name (".polylines.txt", ".polylines", ".cg", ".obj",
// ".json"); throws UnsupportedFormat naming the accepted ones.
SkeletonFormat skeleton_format_from_name(const std::string& name);
bool is_skeleton_file_name(const std::string& name);

Skeleton read_skeleton_bytes(std::string_view bytes, SkeletonFormat format, const std::string& name);
Skeleton read_skeleton(const std::filesystem::path& path);
std::string write_skeleton_bytes(const Skeleton& s, SkeletonFormat format);
void write_skeleton(const Skeleton& s, const std::filesystem::path& path);

}  // namespace cgview
