#pragma once

#include <string>

#include "plumetrace/agent/controllers.hpp"

namespace plumetrace::testing {

/// A controller name that no program registers: the tests of an unknown algorithm use it, never
/// a name a user may well register ("zigzag": examples/zigzag registers it).
inline constexpr const char* kUnregisteredAlgorithm = "no-such-algorithm";

/// The values of controller.algorithm as a refusal lists them: "'casting', 'surge-spiral', ..."
/// (every registered controller, in registry order).
inline std::string algorithm_choices() {
  std::string out;
  for (const Algorithm a : all_algorithms()) {
    out += (out.empty() ? "'" : ", '") + std::string(algorithm_name(a)) + "'";
  }
  return out;
}

}  // namespace plumetrace::testing
