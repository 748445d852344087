#pragma once

#include "plumetrace/core/geometry.hpp"

namespace plumetrace {

/// What a controller perceives at each step: measurements only, never the plume or the source.
struct Observation {
  /// Time since the robot was released (s).
  double time = 0.0;
  /// Binary odor: concentration at the robot reached the threshold.
  bool odor = false;
  /// Pose from the robot's own odometry (m, rad), relative to the release pose: the robot starts
  /// at (0, 0) with heading 0.
  Pose odometry;
  /// Path length travelled since release, from odometry (m).
  double odometer = 0.0;
};

/// The sensor a controller may query during a decision: one noisy wind sample per call.
class WindProbe {
 public:
  virtual ~WindProbe() = default;
  /// Horizontal wind vector (m/s) in the robot frame (+x forward, +y left), with sensor noise.
  virtual Vec2 measure_wind_body() = 0;
};

/// Upwind heading (rad, world frame) from a wind sample in the robot frame and the robot heading.
inline double upwind_heading(const Vec2& wind_body, double robot_heading) {
  return wrap_angle(robot_heading + std::atan2(-wind_body.y, -wind_body.x));
}

/// Kinds of motion a controller can command.
enum class Motion {
  kStop,    ///< stand still
  kTurnTo,  ///< turn on the spot toward `heading`, no translation
  kGo,      ///< turn on the spot toward `heading`, then drive straight at full speed
  kCurve,   ///< drive along an arc of signed `curvature` at the wheel-speed limit
};

/// A controller's decision for one step.
struct Command {
  /// Kind of motion.
  Motion motion = Motion::kStop;
  /// Target heading (rad, in the odometry frame) for kTurnTo and kGo.
  double heading = 0.0;
  /// Signed curvature (1/m, positive turns counter-clockwise) for kCurve.
  double curvature = 0.0;
  /// The controller gives up: the run ends as a failure.
  bool give_up = false;

  /// Stand still.
  static Command stop() { return {}; }
  /// Turn on the spot toward a heading (rad).
  static Command turn_to(double heading) { return {Motion::kTurnTo, heading, 0.0, false}; }
  /// Turn toward a heading (rad), then drive straight.
  static Command go(double heading) { return {Motion::kGo, heading, 0.0, false}; }
  /// Drive along an arc of signed curvature (1/m).
  static Command curve(double curvature) { return {Motion::kCurve, 0.0, curvature, false}; }
  /// End the run as a failure.
  static Command abandon() { return {Motion::kStop, 0.0, 0.0, true}; }
};

}  // namespace plumetrace
