#include "plumetrace/robot.hpp"

#include <cmath>

namespace plumetrace {

namespace {

// drive along an arc of curvature k for path length s (exact integration)
void drive(double k, double s, RobotState& state) {
  Pose& p = state.pose;
  const double dtheta = k * s;
  if (std::fabs(dtheta) < 1e-12) {
    p.x += s * std::cos(p.heading);
    p.y += s * std::sin(p.heading);
  } else {
    p.x += (std::sin(p.heading + dtheta) - std::sin(p.heading)) / k;
    p.y -= (std::cos(p.heading + dtheta) - std::cos(p.heading)) / k;
    p.heading = wrap_angle(p.heading + dtheta);
  }
  state.odometer += s;
}

}  // namespace

void step_robot(const RobotParams& params, const Command& command, double dt, RobotState& state) {
  switch (command.motion) {
    case Motion::kStop:
      return;
    case Motion::kTurnTo:
    case Motion::kGo: {
      // turn on the spot at the wheel-speed limit; drive with whatever time is left
      const double omega = turn_rate(params);
      const double error = wrap_angle(command.heading - state.pose.heading);
      const double turn_time = std::fabs(error) / omega;
      if (turn_time >= dt) {
        state.pose.heading = wrap_angle(state.pose.heading + std::copysign(omega * dt, error));
        return;
      }
      state.pose.heading = wrap_angle(command.heading);
      if (command.motion == Motion::kGo) drive(0.0, params.wheel_speed * (dt - turn_time), state);
      return;
    }
    case Motion::kCurve: {
      // why: the outer wheel runs at the limit, so the centre slows on tight curves (SPEC 4)
      const double v =
          params.wheel_speed / (1.0 + std::fabs(command.curvature) * params.axle / 2.0);
      drive(command.curvature, v * dt, state);
      return;
    }
  }
}

}  // namespace plumetrace
