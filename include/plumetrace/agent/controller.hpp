#pragma once

#include <cstddef>
#include <string_view>

#include "plumetrace/agent/measurement.hpp"
#include "plumetrace/core/config.hpp"
#include "plumetrace/core/geometry.hpp"
#include "plumetrace/core/rng.hpp"

namespace plumetrace {

/// A plume-tracking algorithm: turns measurements into motion commands.
/// why: controllers include only geometry and measurement (and config, for their params' keys),
/// so they cannot peek at the world.
class Controller {
 public:
  virtual ~Controller() = default;
  /// Decides this step's command; may sample the wind through `wind` (at state switches only).
  virtual Command step(const Observation& obs, WindProbe& wind) = 0;
  /// Name of the current state, for traces.
  virtual std::string_view state() const = 0;
  /// Number of times the plume was declared lost so far.
  virtual int losses() const = 0;
};

/// The longest state name a controller may report (bytes). why: traces store the name of every
/// step, and the viewer copies it per frame: a 1 MB name made a 5.8 MB trace take 4.8 GB to view
/// (issue 22, G8).
inline constexpr std::size_t kMaxStateName = 64;

/// Throws ConfigError saying why when `name` is not a state name: longer than kMaxStateName, or
/// holding a control character.
void check_state_name(std::string_view name);

/// Tracks the path length since the last odor detection; the robot starts in the plume.
class LossTracker {
 public:
  /// Records this step's odor flag and odometer.
  void observe(const Observation& obs) {
    if (obs.odor) last_odor_odometer_ = obs.odometer;
  }
  /// True once the robot has travelled d_lost (m) since the last detection.
  bool lost(const Observation& obs, double d_lost) const {
    return obs.odometer - last_odor_odometer_ >= d_lost;
  }

 private:
  double last_odor_odometer_ = 0.0;
};

/// Guesses the plume side (+1 left of upwind, -1 right) after a loss: the robot drifted to the side
/// its surge heading erred toward, so the plume is on the other side; a tie is broken at random.
int guess_plume_side(double surge_heading, double upwind_now, Rng& rng);

}  // namespace plumetrace
