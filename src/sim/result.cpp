#include "plumetrace/sim/result.hpp"

#include <string>

#include "plumetrace/core/errors.hpp"

namespace plumetrace {

static_assert(static_cast<std::size_t>(Outcome::kWrongDeclaration) + 1 == kOutcomeNames.size(),
              "every outcome has a name");

std::string_view outcome_name(Outcome outcome) {
  const auto i = static_cast<std::size_t>(outcome);
  return i < kOutcomeNames.size() ? kOutcomeNames[i] : "";
}

Outcome parse_outcome(std::string_view name) {
  std::string names;
  for (std::size_t i = 0; i < kOutcomeNames.size(); ++i) {
    if (kOutcomeNames[i] == name) return static_cast<Outcome>(i);
    names += (i ? ", " : "") + std::string(kOutcomeNames[i]);
  }
  throw ConfigError("unknown outcome '" + std::string(name) + "' (one of " + names + ")");
}

}  // namespace plumetrace
