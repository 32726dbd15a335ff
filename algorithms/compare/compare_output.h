// compare_output: whether a student's output matches a teacher's reference
// output, within an assignment's tolerance, and a reason the student reads.
//
//   scalar_field  relative:    mean_i |r_i - s_i| / scale <= tolerance, scale = max(s) - min(s)
//                              (max_i |s_i|, at least 1e-12, for a constant reference)
//                 correlation: Pearson's correlation of r and s >= tolerance
//   mesh          hausdorff:   max(h(R,S), h(S,R)) / diagonal of S's bounding box <= tolerance,
//                              h(A,B) = max over samples a of A of min over B of |a - b|
//   skeleton      hausdorff:   the same over points along the edges (skeleton_distance)
//   metrics       tolerance:   |r_k - s_k| <= tol_k * max(|s_k|, 1e-12) for each key k
//
// r is the result, s the reference.  Positions where the reference's field is
// not finite are not compared.  What the student got wrong (another kind, a
// field of another size, NaN, a missing metric) is a failing Verdict; what
// the teacher got wrong (an empty or invalid reference, a spec that does not
// fit it) throws InvalidInput.  The same inputs give the same numbers on
// every call: the mesh is sampled on a grid, never at random.
//
//   CompareSpec spec = compare_spec_from_json({{"method", "correlation"}}, OutputKind::scalar_field);
//   Verdict v = compare_output(result_field, reference_field, spec);  // v.pass, v.reason
#pragma once

#include <map>
#include <nlohmann/json_fwd.hpp>
#include <string>

#include "artifacts/artifact_codec.h"

namespace cgview {

// How a result is compared with its reference (an assignment's setting).
struct CompareSpec {
  std::string method;     // scalar_field: "relative" (default) or "correlation"; mesh: "hausdorff";
                          // skeleton: "hausdorff"; metrics: "tolerance"
  double tolerance = -1;  // relative: the largest mean error allowed, as a fraction of the reference's range
                          // (default 0.03); correlation: the smallest Pearson correlation allowed (default
                          // 0.95); hausdorff: the largest symmetric Hausdorff distance over the reference's
                          // bounding-box diagonal (default 0.01); metrics: the default relative tolerance
                          // per key (default 0.01)
  std::map<std::string, double> keys;  // metrics: a relative tolerance per key (overrides tolerance); only
                                       // these keys are compared when given
};

// Reads {"method", "tolerance", "keys"} (each optional; null or {} for all
// defaults) for an output of `kind` and fills the defaults.  Throws
// InvalidInput naming what is wrong: an unknown field, an unknown method for
// that kind, a negative tolerance, a correlation tolerance outside [-1, 1],
// keys for a kind other than metrics, or a kind that cannot be compared
// (voxel_grid, text, animation, vector_field).
CompareSpec compare_spec_from_json(const nlohmann::json& j, OutputKind kind);
// {"method", "tolerance"} and "keys" when there are any: what
// compare_spec_from_json reads back as the same spec.
nlohmann::json to_json(const CompareSpec& spec);

struct Verdict {
  bool pass = false;
  // What a student reads: "within tolerance: mean error 1.2% of the range (3% allowed)",
  // "correlation 0.81 under the 0.95 required", "missing metric 'genus'", ...
  std::string reason;
  // scalar_field: mean_error, max_error (fractions of the scale), scale, or correlation;
  // mesh: hausdorff (over the diagonal), diagonal; skeleton: hausdorff, mean (over the
  // diagonal), diagonal; metrics: each key's relative error |r - s| / max(|s|, 1e-12).
  std::map<std::string, double> measures;
};

// result and reference are artifact values.  spec as compare_spec_from_json
// returns it (defaults filled) for the reference's kind; throws InvalidInput
// when it is not one, and for a reference that cannot be compared against
// (no finite value, no faces, an empty bounding box, no metrics).
Verdict compare_output(const ArtifactValue& result, const ArtifactValue& reference, const CompareSpec& spec);

}  // namespace cgview
