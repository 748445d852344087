#pragma once

#include <cmath>

#include "plumetrace/agent/measurement.hpp"

namespace plumetrace::testing {

/// A noiseless wind probe whose upwind direction in the odometry frame is `upwind` (rad), seen
/// from the heading the test sets; counts its samples.
class FixedWind final : public WindProbe {
 public:
  explicit FixedWind(double upwind = kPi) : upwind(upwind) {}
  Vec2 measure_wind_body() override {
    ++calls;
    // the air moves opposite to upwind; the probe reports it in the robot frame
    return rotate({std::cos(upwind + kPi), std::sin(upwind + kPi)}, -heading);
  }
  double upwind;         ///< upwind direction (rad, odometry frame)
  double heading = 0.0;  ///< the robot's heading (rad, odometry frame)
  int calls = 0;         ///< samples taken
};

/// Observations of a robot that obeys go(heading) at once: each call turns it to the
/// commanded heading and drives it `advance` (m).
struct InstantRobot {
  Observation obs;  ///< what the controller sees next
  /// Applies `command`: the heading is reached and the odometer advances by `advance` (m).
  void obey(const Command& command, double advance) {
    obs.odometry.heading = command.heading;
    obs.odometry.x += advance * std::cos(command.heading);
    obs.odometry.y += advance * std::sin(command.heading);
    obs.odometer += advance;
  }
};

}  // namespace plumetrace::testing
