#include "zigzag.hpp"

#include "plumetrace/agent/controllers.hpp"

namespace zigzag {

// the one registration line: "zigzag" becomes a value of controller.algorithm, and the keys of
// ZigzagParams config keys of every subcommand of this program
const plumetrace::RegisterController<Zigzag, ZigzagParams> kRegistered("zigzag");

plumetrace::Command Zigzag::step(const plumetrace::Observation& obs, plumetrace::WindProbe& wind) {
  // a new leg at release and after every `leg` metres: measure the wind, take the other side
  if (!started_ || obs.odometer - leg_start_ >= params_.leg) {
    side_ = started_ ? -side_ : rng_.sign();
    started_ = true;
    heading_ = plumetrace::upwind_heading(wind.measure_wind_body(), obs.odometry.heading) +
               side_ * params_.angle;
    leg_start_ = obs.odometer;
  }
  return plumetrace::Command::go(heading_);
}

}  // namespace zigzag
