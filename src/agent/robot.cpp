#include "plumetrace/agent/robot.hpp"

#include <algorithm>
#include <cmath>

#include "plumetrace/core/math.hpp"

namespace plumetrace {

namespace {

// drive along an arc of curvature k for path length s (exact integration)
void drive(double k, double s, RobotState& state) {
  Pose& p = state.pose;
  const double dtheta = k * s;
  if (std::fabs(dtheta) < 1e-12) {
    p.x += s * math::cos(p.heading);
    p.y += s * math::sin(p.heading);
  } else {
    p.x += (math::sin(p.heading + dtheta) - math::sin(p.heading)) / k;
    p.y -= (math::cos(p.heading + dtheta) - math::cos(p.heading)) / k;
    p.heading = wrap_angle(p.heading + dtheta);
  }
  state.odometer += s;
}

// drive along an arc for path length s, stopping where the body meets the obstacle
void drive_clear(const RobotParams& params, const Obstacle& obstacle, double k, double s,
                 RobotState& state) {
  if (obstacle.radius > 0.0) {
    const double contact = obstacle.radius + params.radius;
    // why: the same straight-line test as drive, so the clipped move takes the same path
    const double k_path = std::fabs(k * s) < 1e-12 ? 0.0 : k;
    const double free = contact_length(state.pose, k_path, obstacle.center, contact);
    if (free <= s) {
      drive(k, free, state);
      state.touching = true;
      return;
    }
  }
  state.touching = false;
  drive(k, s, state);
}

}  // namespace

double contact_length(const Pose& pose, double k, const Vec2& center, double contact) {
  // already in contact: moving inward is blocked at once, moving outward is free
  const double wx = pose.x - center.x, wy = pose.y - center.y;
  const double along = wx * math::cos(pose.heading) + wy * math::sin(pose.heading);
  const double q = wx * wx + wy * wy - contact * contact;
  if (q <= 0.0) return along < 0.0 ? 0.0 : INFINITY;
  if (k == 0.0) {
    // straight: the smaller root of u^2 + 2 along u + q = 0, written without cancellation
    const double disc = along * along - q;
    if (along >= 0.0 || disc < 0.0) return INFINITY;
    return q / (-along + std::sqrt(disc));
  }
  // arc about a = pose + (-sin h, cos h) / k: the centre is at angle phi = h + k u with
  // p - a = (sin phi, -cos phi) / k, so |p - c|^2 = contact^2 where D sin(phi - psi) = k m
  const double ax = pose.x - math::sin(pose.heading) / k;
  const double ay = pose.y + math::cos(pose.heading) / k;
  const double dx = center.x - ax, dy = center.y - ay;
  const double d2 = dx * dx + dy * dy;
  const double m = 0.5 * (1.0 / (k * k) + d2 - contact * contact);
  const double g = k * m / std::sqrt(d2);
  if (!(std::fabs(g) <= 1.0)) return INFINITY;
  const double psi = math::atan2(dy, dx);
  double best = INFINITY;
  for (const double phi : {psi + math::asin(g), psi + kPi - math::asin(g)}) {
    // the turn (rad) from the heading to phi in the arc's own direction
    double turn = std::fmod(k > 0.0 ? phi - pose.heading : pose.heading - phi, 2.0 * kPi);
    if (turn < 0.0) turn += 2.0 * kPi;
    best = std::min(best, turn / std::fabs(k));
  }
  return best;
}

void step_robot(const RobotParams& params, const Command& command, double dt, RobotState& state,
                const Obstacle& obstacle) {
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
      if (command.motion == Motion::kGo) {
        drive_clear(params, obstacle, 0.0, params.wheel_speed * (dt - turn_time), state);
      }
      return;
    }
    case Motion::kCurve: {
      // why: the outer wheel runs at the limit, so the centre slows on tight curves
      // (docs/model.md section 6)
      const double v =
          params.wheel_speed / (1.0 + std::fabs(command.curvature) * params.axle / 2.0);
      drive_clear(params, obstacle, command.curvature, v * dt, state);
      return;
    }
  }
}

}  // namespace plumetrace
