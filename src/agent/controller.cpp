#include "plumetrace/agent/controller.hpp"

namespace plumetrace {

int guess_plume_side(double surge_heading, double upwind_now, Rng& rng) {
  const double error = wrap_angle(surge_heading - upwind_now);
  if (error > 0.0) return -1;
  if (error < 0.0) return 1;
  return rng.sign();
}

}  // namespace plumetrace
