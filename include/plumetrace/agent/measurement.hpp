#pragma once

#include <array>
#include <cmath>
#include <span>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/math.hpp"

namespace plumetrace {

/// What a controller reads besides time, odometry, the binary odor and the wind probe, which
/// every controller gets: flags to combine with |. A controller declares them (Controller::reads)
/// so that what nobody asks for is not computed: the paper's binary controllers ask for nothing
/// more and pay nothing new (docs/agents.md).
enum Reads : unsigned {
  kReadsBinary = 0,          ///< the binary odor, time, odometry and the wind probe only
  kReadsConcentration = 1u,  ///< the odor sensor's reading (Observation::concentration)
  kReadsMessages = 1u << 1,  ///< messages from teammates (Observation::messages)
};

/// Numbers in one message (doubles): a position estimate and two more, or anything else.
inline constexpr std::size_t kMessageSize = 4;

/// A message a robot broadcast to its team (docs/agents.md, "Communication").
struct Message {
  /// The sender's index in its team.
  int from = 0;
  /// The sender's time since release when it sent the message (s).
  double sent = 0.0;
  /// What the sender's controller put there.
  std::array<double, kMessageSize> data{};
};

/// What a controller perceives at each step: measurements only, never the plume or the source.
struct Observation {
  /// Time since the robot was released (s).
  double time = 0.0;
  /// Binary odor: the odor sensor's reading reached the threshold.
  bool odor = false;
  /// Pose from the robot's own odometry (m, rad), relative to the release pose: the robot starts
  /// at (0, 0) with heading 0.
  Pose odometry;
  /// Path length travelled since release, from odometry (m).
  double odometer = 0.0;
  /// The odor sensor's reading (concentration units of the odor model, after the sensor model);
  /// NaN unless the controller reads kReadsConcentration.
  double concentration = NAN;
  /// Messages delivered this step from teammates in range, in the order (sent, from); empty
  /// unless the controller reads kReadsMessages. Valid during the call to Controller::step.
  std::span<const Message> messages;
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
  return wrap_angle(robot_heading + math::atan2(-wind_body.y, -wind_body.x));
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
  /// The controller declares where the source is: the run ends, scored by the supervisor
  /// (docs/agents.md, "Source declaration"). The motion of this command is not made.
  bool declare = false;
  /// The declared source position (m, in the odometry frame) when `declare`.
  Vec2 source;
  /// Broadcast `message` to teammates this step (delivered from the next step on).
  bool send = false;
  /// The message's numbers when `send`.
  std::array<double, kMessageSize> message{};

  /// Stand still.
  static Command stop() { return {}; }
  /// Turn on the spot toward a heading (rad).
  static Command turn_to(double heading) {
    Command c;
    c.motion = Motion::kTurnTo;
    c.heading = heading;
    return c;
  }
  /// Turn toward a heading (rad), then drive straight.
  static Command go(double heading) {
    Command c;
    c.motion = Motion::kGo;
    c.heading = heading;
    return c;
  }
  /// Drive along an arc of signed curvature (1/m).
  static Command curve(double curvature) {
    Command c;
    c.motion = Motion::kCurve;
    c.curvature = curvature;
    return c;
  }
  /// End the run as a failure.
  static Command abandon() {
    Command c;
    c.give_up = true;
    return c;
  }
  /// End the run by declaring the source at `where` (m, odometry frame).
  static Command declare_source(const Vec2& where) {
    Command c;
    c.declare = true;
    c.source = where;
    return c;
  }
  /// This command, also broadcasting `data` to teammates.
  Command with_message(const std::array<double, kMessageSize>& data) const {
    Command c = *this;
    c.send = true;
    c.message = data;
    return c;
  }
};

}  // namespace plumetrace
