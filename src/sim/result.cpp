#include "plumetrace/sim/result.hpp"

#include <array>
#include <string>
#include <utility>

#include "plumetrace/core/errors.hpp"

namespace plumetrace {

namespace {

// every outcome and its name, in declaration order: the one table both directions read
constexpr std::array<std::pair<Outcome, std::string_view>, 5> kOutcomes{{
    {Outcome::kRunning, "running"},
    {Outcome::kSuccess, "success"},
    {Outcome::kWall, "wall"},
    {Outcome::kTimeout, "timeout"},
    {Outcome::kGaveUp, "gave_up"},
}};

}  // namespace

std::string_view outcome_name(Outcome outcome) {
  for (const auto& [o, name] : kOutcomes) {
    if (o == outcome) return name;
  }
  return "";
}

Outcome parse_outcome(std::string_view name) {
  std::string names;
  for (const auto& [o, n] : kOutcomes) {
    if (n == name) return o;
    names += (names.empty() ? "" : ", ") + std::string(n);
  }
  throw ConfigError("unknown outcome '" + std::string(name) + "' (one of " + names + ")");
}

}  // namespace plumetrace
