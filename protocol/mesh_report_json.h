// The JSON form of a mesh report, shared by `cgview info --json` and the
// server's mesh metadata.  Keys: vertices, faces, edges, bbox {min, max},
// components, boundary_loops, genus (null unless manifold and oriented),
// manifold, degenerate_faces, and the details of MeshReport.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include "core/mesh_report.h"

namespace cgview::protocol {

nlohmann::json to_json(const MeshReport& report);

}  // namespace cgview::protocol
