#pragma once

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"

namespace plumetrace {

/// Khepera III differential drive (docs/model.md section 6).
struct RobotParams {
  /// Body radius (m).
  double radius = 0.065;
  /// Distance between the wheels (m).
  double axle = 0.0885;
  /// Wheel-speed limit (m/s); the forward speed on straight lines.
  double wheel_speed = 0.106;
  /// Start position and heading (m, rad): 14.5 m downwind of the source, facing upwind. x and y
  /// are derived from the source unless set (derive_scenario, sim/scenario.hpp).
  Pose start{15.5, 0.0, kPi};
  /// Start position relative to the source centre (m): robot.start_x = source.x + x and
  /// robot.start_y = source.y + y, where those are "auto".
  Vec2 start_offset{14.5, 0.0};
  /// robot.start_x is "auto": it follows the source.
  bool start_x_auto = true;
  /// robot.start_y is "auto": it follows the source.
  bool start_y_auto = true;

  /// The config keys (core/config.hpp).
  template <class V>
  void fields(V& v) {
    const double deg = kPi / 180.0;
    v("radius", radius, "body radius (m)", kPositive);
    v("axle", axle, "distance between the wheels (m)", kPositive);
    v("wheel_speed", wheel_speed, "wheel-speed limit = straight-line speed (m/s)", kPositive);
    v("start_x", start.x, "start position x (m)", kAnyNumber, start_x_auto);
    v("start_y", start.y, "start position y (m)", kAnyNumber, start_y_auto);
    v.input("start_offset_x", start_offset.x,
            "start x relative to the source: robot.start_x = source.x + this (m)", kAnyNumber,
            start_x_auto);
    v.input("start_offset_y", start_offset.y,
            "start y relative to the source: robot.start_y = source.y + this (m)", kAnyNumber,
            start_y_auto);
    v("start_heading_deg", start.heading, "start heading (deg, counter-clockwise from +x)",
      NumberSpec{.min = -kPi - 1e-12, .max = kPi + 1e-12, .scale = deg});
  }
};

/// The robot's true state.
struct RobotState {
  /// True pose (m, rad).
  Pose pose;
  /// Path length of the centre since release (m); turning on the spot adds nothing.
  double odometer = 0.0;
  /// The body touches the obstacle: the last move stopped at contact.
  bool touching = false;
};

/// A solid disc the robot body cannot enter (a collidable source cylinder seen from above).
struct Obstacle {
  /// Centre (m).
  Vec2 center;
  /// Radius (m); 0 means no obstacle.
  double radius = 0.0;
};

/// Turn rate on the spot with both wheels at the limit (rad/s).
inline double turn_rate(const RobotParams& p) { return 2.0 * p.wheel_speed / p.axle; }

/// Path length (m) the centre can drive from `pose` along an arc of curvature k (1/m, 0:
/// straight) before it comes within `contact` (m) of `center`; infinity if it never does.
double contact_length(const Pose& pose, double k, const Vec2& center, double contact);

/// Advances the robot by dt under a command (exact arcs; turning on the spot, then driving).
/// A move that would bring the body into `obstacle` stops at contact and sets `touching`.
void step_robot(const RobotParams& params, const Command& command, double dt, RobotState& state,
                const Obstacle& obstacle = {});

}  // namespace plumetrace
