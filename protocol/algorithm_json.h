// The JSON of the algorithm registry: each algorithm with a JSON Schema of
// its parameters (GET /api/v1/algorithms, `cgview list --json`), and the
// conversion of a job's JSON parameters to checked values.
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "registry/registry.h"

namespace cgview::protocol {

nlohmann::json to_json(const Algorithm& algorithm);
// The description back (name, title, inputs, outputs, parameters with their
// types, defaults, ranges and choices; no `run`): what a plugin's algorithm
// is checked against by a server that does not load it.  Throws
// InvalidInput for a description it cannot read.
Algorithm algorithm_from_json(const nlohmann::json& description);
// {"rays": 25, ...} to checked values; throws InvalidInput naming the
// parameter and the rule it broke (unknown name, type, range, choices).
std::map<std::string, ParamValue> params_from_json(const Algorithm& algorithm, const nlohmann::json& params);

}  // namespace cgview::protocol
