#include "plumetrace/agent/controllers/surge_spiral.hpp"

#include <cmath>

namespace plumetrace {

double spiral_arc_length(double b, double theta) {
  return 0.5 * b * (theta * std::sqrt(1.0 + theta * theta) + std::asinh(theta));
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
  return (t2 + 2.0) / (b * std::pow(t2 + 1.0, 1.5));
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

Command SurgeSpiral::step(const Observation& obs, WindProbe& wind) {
  tracker_.observe(obs);
  if (!started_) {
    started_ = true;
    heading_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
  }
  switch (state_) {
    case State::kSurge:
      if (tracker_.lost(obs, params_.d_lost)) {
        // lost: measure wind, guess the plume side, spiral toward it starting upwind
        ++losses_;
        const double upwind = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        spiral_.start(params_.d_gap, params_.start_radius,
                      guess_plume_side(heading_, upwind, rng_));
        heading_ = upwind;
        aligned_ = false;
        state_ = State::kSpiral;
      }
      break;
    case State::kSpiral:
      if (obs.odor) {
        heading_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        state_ = State::kSurge;
      }
      break;
  }
  if (state_ == State::kSurge) return Command::go(heading_);

  if (!aligned_) {
    if (std::fabs(wrap_angle(obs.odometry.heading - heading_)) > 1e-9) {
      return Command::turn_to(heading_);
    }
    aligned_ = true;
    spiral_.anchor(obs.odometer);
  }
  return Command::curve(spiral_.curvature(obs.odometer));
}

std::string_view SurgeSpiral::state() const { return state_ == State::kSurge ? "surge" : "spiral"; }

}  // namespace plumetrace
