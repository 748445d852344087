#include "plumetrace/agent/controller.hpp"

#include <cmath>
#include <string>

#include "plumetrace/core/errors.hpp"
#include "plumetrace/core/files.hpp"
#include "plumetrace/core/math.hpp"

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
  return 2.0 * math::atan((1.0 - rho) / (1.0 + rho) * math::tan(kPi * (u - 0.5)));
}

int guess_plume_side(double surge_heading, double upwind_now, Rng& rng) {
  const double error = wrap_angle(surge_heading - upwind_now);
  if (error > 0.0) return -1;
  if (error < 0.0) return 1;
  return rng.sign();
}

double spiral_arc_length(double b, double theta) {
  return 0.5 * b * (theta * std::sqrt(1.0 + theta * theta) + math::asinh(theta));
}

double spiral_angle_at(double b, double s, double guess) {
  double theta = guess;
  for (int i = 0; i < 50; ++i) {
    const double f = spiral_arc_length(b, theta) - s;
    const double step = f / (b * std::sqrt(1.0 + theta * theta));
    theta -= step;
    if (theta < 0.0) theta = 0.0;
    if (std::fabs(step) < 1e-13) break;
  }
  return theta;
}

double spiral_curvature(double b, double theta) {
  const double t2 = theta * theta;
  return (t2 + 2.0) / (b * math::pow(t2 + 1.0, 1.5));
}

void SpiralPath::start(double d_gap, double start_radius, int curl) {
  // why: r = b theta puts successive turns d_gap apart; the Khepera III toolbox's spiral starts
  // with a finite curvature, i.e. at a radius r0 on the spiral, not at its centre
  // (docs/model.md)
  b_ = d_gap / (2.0 * kPi);
  theta_ = start_radius / b_;
  arc_offset_ = spiral_arc_length(b_, theta_);
  curl_ = curl;
}

double SpiralPath::curvature(double odometer) {
  // why: follow r = b theta by its curvature at the path length covered so far, counted from
  // the spiral's centre
  theta_ = spiral_angle_at(b_, arc_offset_ + (odometer - s0_), theta_);
  return curl_ * spiral_curvature(b_, theta_);
}

}  // namespace plumetrace
