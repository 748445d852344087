#include "plumetrace/agent/controllers/surge_spiral.hpp"

#include <cmath>

namespace plumetrace {

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
