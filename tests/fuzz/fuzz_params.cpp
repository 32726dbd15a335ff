// Job submission's parameter validation (protocol/algorithm_json.h's
// params_from_json, then check_param): the JSON of a job's "params" against
// an algorithm with a parameter of every type, ranges and choices.
#include <nlohmann/json.hpp>

#include "algorithm_json.h"
#include "fuzz.h"
#include "io/parse_json.h"
#include "registry/registry.h"

namespace {
cgview::Algorithm every_type() {
  using cgview::ParamType;
  cgview::Algorithm a;
  a.info.name = "every_type";
  a.params = {{"count", ParamType::integer, 5LL, {.min = 1, .max = 100}},
              {"scale", ParamType::number, 1.0, {.min = 0, .max = 1e6}},
              {"open", ParamType::boolean, false, {}},
              {"mode", ParamType::choice, std::string("solid"), {.choices = {"solid", "surface"}}},
              {"note", ParamType::text, std::string(), {}},
              {"faces", ParamType::faces, cgview::Ids{}, {}},
              {"vertices", ParamType::vertices, cgview::Ids{}, {}}};
  return a;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cgview;
  static const Algorithm algorithm = every_type();
  const nlohmann::json params = parse_json_or_discarded(fuzz::text(data, size));
  if (params.is_discarded()) return 0;
  return fuzz::expect_answer([&] {
    for (const auto& [name, value] : protocol::params_from_json(algorithm, params)) (void)to_string(value);
  });
}
