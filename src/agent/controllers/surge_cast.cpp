#include "plumetrace/agent/controllers/surge_cast.hpp"

namespace plumetrace {

Command SurgeCast::step(const Observation& obs, WindProbe& wind) {
  tracker_.observe(obs);
  if (!started_) {
    started_ = true;
    heading_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
  }
  const double cast_length = obs.odometer - cast_start_;
  switch (state_) {
    case State::kSurge:
      if (tracker_.lost(obs, params_.d_lost)) {
        // lost: measure wind, guess the side, cast toward it
        ++losses_;
        upwind_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        side_ = guess_plume_side(heading_, upwind_, rng_);
        cast_start_ = obs.odometer;
        state_ = State::kCast1;
      }
      break;
    case State::kCast1:
    case State::kCast2:
      if (obs.odor) {
        heading_ = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        state_ = State::kSurge;
      } else if (state_ == State::kCast1 && cast_length >= params_.d_cast) {
        // first cast missed: turn round and go twice as far the other way
        cast_start_ = obs.odometer;
        state_ = State::kCast2;
      } else if (state_ == State::kCast2 && cast_length >= 2.0 * params_.d_cast) {
        return Command::abandon();
      }
      break;
  }
  switch (state_) {
    case State::kSurge:
      return Command::go(heading_);
    case State::kCast1:
      return Command::go(upwind_ + side_ * kPi / 2.0);
    case State::kCast2:
      return Command::go(upwind_ - side_ * kPi / 2.0);
  }
  return Command::stop();
}

std::string_view SurgeCast::state() const {
  switch (state_) {
    case State::kSurge:
      return "surge";
    case State::kCast1:
      return "cast1";
    case State::kCast2:
      return "cast2";
  }
  return "";
}

}  // namespace plumetrace
