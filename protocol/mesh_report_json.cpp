#include "mesh_report_json.h"

#include <nlohmann/json.hpp>

namespace cgview::protocol {

nlohmann::json to_json(const MeshReport& r) {
  using nlohmann::json;
  auto vec = [](Vec3 v) { return json::array({v.x, v.y, v.z}); };
  auto opt = [](const auto& o) { return o ? json(*o) : json(nullptr); };
  return json{
      {"vertices", r.vertices},
      {"faces", r.faces},
      {"edges", r.edges},
      {"bbox", r.bbox.empty() ? json(nullptr) : json{{"min", vec(r.bbox.min)}, {"max", vec(r.bbox.max)}}},
      {"components", r.components},
      {"boundary_loops", r.boundary_loops},
      {"genus", opt(r.genus)},
      {"manifold", r.manifold},
      {"degenerate_faces", r.degenerate_faces},
      {"duplicate_faces", r.duplicate_faces},
      {"closed", r.closed},
      {"oriented", r.oriented},
      {"faces_inward", r.faces_inward},
      {"isolated_vertices", r.isolated_vertices},
      {"boundary_edges", r.boundary_edges},
      {"non_manifold_edges", r.non_manifold_edges},
      {"non_manifold_vertices", r.non_manifold_vertices},
      {"inconsistent_edges", r.inconsistent_edges},
      {"euler_characteristic", opt(r.euler_characteristic)},
      {"area", r.area},
      {"volume", opt(r.volume)},
      {"points", r.point_cloud()},
  };
}

}  // namespace cgview::protocol
