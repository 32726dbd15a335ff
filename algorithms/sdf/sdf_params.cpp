#include "sdf/sdf_params.h"

#include <string>

namespace cgview::sdf {

void postprocess(const Mesh& mesh, const Adjacency& graph, std::vector<double>& values, const SdfParamFields& p,
                 Context& ctx) {
  fill_missing(mesh, graph, values);
  if (p.smooth) bilateral_smooth(graph, values, p.window, &ctx);
}

std::vector<Artifact> sdf_fields(const Mesh& mesh, const std::string& name, const std::vector<double>& values) {
  ScalarField raw{name, Location::face, ColorHint::standard, {values.begin(), values.end()}};
  const std::vector<double> n = normalize_linear(values);
  ScalarField normalized{name + "_normalized", Location::face, ColorHint::standard, {n.begin(), n.end()}};
  ScalarField per_vertex = face_to_vertex(mesh, raw);
  per_vertex.name = name + "_vertex";
  return {
      {name, std::move(raw)}, {name + "_normalized", std::move(normalized)}, {name + "_vertex", std::move(per_vertex)}};
}

void warn_missing(const RawSdf& raw, std::vector<std::string>& warnings) {
  if (raw.missing)
    warnings.push_back(std::to_string(raw.missing) + " of " + std::to_string(raw.values.size()) +
                       " faces had no ray that found the inside (an open or degenerate mesh): they take their "
                       "neighbours' mean, else the smallest value");
}

}  // namespace cgview::sdf
