#include "plumetrace/agent/controllers/casting.hpp"

namespace plumetrace {

Command Casting::step(const Observation& obs, WindProbe& wind) {
  tracker_.observe(obs);
  if (!started_) {
    // release: UPWIND(s) with s chosen at random
    started_ = true;
    side_ = rng_.sign();
    heading_ =
        upwind_heading(wind.measure_wind_body(), obs.odometry.heading) + side_ * params_.beta;
  }
  switch (state_) {
    case State::kUpwind:
      if (tracker_.lost(obs, params_.d_lost)) {
        // lost: measure wind, go crosswind toward -s
        ++losses_;
        const double upwind = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        heading_ = upwind - side_ * kPi / 2.0;
        state_ = State::kCrosswind;
      }
      break;
    case State::kCrosswind:
      if (obs.odor) {
        // odor hit: measure wind, go UPWIND(-s) (or UPWIND(s) with reacquire_side = same)
        if (params_.reacquire_side == ReacquireSide::kAlternate) side_ = -side_;
        const double upwind = upwind_heading(wind.measure_wind_body(), obs.odometry.heading);
        heading_ = upwind + side_ * params_.beta;
        state_ = State::kUpwind;
      }
      break;
  }
  return Command::go(heading_);
}

std::string_view Casting::state() const {
  return state_ == State::kUpwind ? "upwind" : "crosswind";
}

}  // namespace plumetrace
