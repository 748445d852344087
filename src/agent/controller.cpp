#include "plumetrace/agent/controller.hpp"

#include <cmath>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"

namespace plumetrace {

void check_state_name(std::string_view name) {
  if (name.size() > kMaxStateName) {
    throw ConfigError("a controller's state name must have at most " +
                      std::to_string(kMaxStateName) + " bytes (got " + std::to_string(name.size()) +
                      ")");
  }
  if (control_character(name) != std::string_view::npos) {
    throw ConfigError("a controller's state name holds a control character");
  }
}

double wrapped_cauchy(double rho, Rng& rng) {
  // inverse of the law's distribution function: phi = 2 atan((1 - rho) / (1 + rho) tan(pi (u -
  // 1/2))), u uniform
  const double u = rng.uniform();
  return 2.0 * std::atan((1.0 - rho) / (1.0 + rho) * std::tan(kPi * (u - 0.5)));
}

int guess_plume_side(double surge_heading, double upwind_now, Rng& rng) {
  const double error = wrap_angle(surge_heading - upwind_now);
  if (error > 0.0) return -1;
  if (error < 0.0) return 1;
  return rng.sign();
}

}  // namespace plumetrace
