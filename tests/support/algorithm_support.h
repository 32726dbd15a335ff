// Running a registered algorithm in a test and picking its outputs, for the
// suites that link the algorithms (header-only: test_support links no registry).
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <variant>

#include "registry/registry.h"

namespace cgview::test {

using Values = std::map<std::string, ParamValue>;

// Runs the algorithm of that name with no progress or cancellation.
inline AlgorithmResult run_algorithm(const std::string& name, const Inputs& inputs, const Values& values = {}) {
  Context ctx;
  return find_algorithm(name).run(inputs, values, ctx);
}

// The artifact of that name, of type T; throws when there is none.
template <class T>
const T& artifact(const AlgorithmResult& r, const std::string& name) {
  for (const Artifact& a : r.artifacts)
    if (a.name == name) return std::get<T>(a.value);
  throw std::runtime_error("no artifact " + name);
}

}  // namespace cgview::test
