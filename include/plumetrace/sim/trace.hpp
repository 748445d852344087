#pragma once

#include <string>
#include <vector>

#include "plumetrace/core/geometry.hpp"
#include "plumetrace/sim/world.hpp"

namespace plumetrace {

/// One row of a trace: the state after a step.
struct TraceStep {
  /// Time since release (s).
  double time = 0.0;
  /// True robot pose (m, rad).
  Pose pose;
  /// Path length so far (m).
  double odometer = 0.0;
  /// Controller state after its decision.
  std::string state;
  /// Odor perceived at this step.
  bool odor = false;
  /// Concentration at the sensor.
  double concentration = 0.0;
  /// Wind samples the controller took this step (0 or more).
  int wind_samples = 0;
  /// Last wind sample of this step in the robot frame (m/s); meaningful when wind_samples > 0.
  Vec3 wind_body;
};

/// Positions and widths of every filament at one instant.
struct FilamentSnapshot {
  /// Time since release (s); the first snapshot is at release.
  double time = 0.0;
  std::vector<double> x;  ///< positions x (m)
  std::vector<double> y;  ///< positions y (m)
  std::vector<double> z;  ///< positions z (m)
  std::vector<double> w;  ///< widths (m)
};

/// Everything recorded about one run, for plots and viewers.
struct Trace {
  std::vector<TraceStep> steps;             ///< one row at release, then one per step
  std::vector<FilamentSnapshot> snapshots;  ///< filaments at the snapshot interval
};

/// Records a World into a Trace; use as the StepObserver of run_once.
class TraceRecorder {
 public:
  /// Snapshots the filaments every `snapshot_interval` seconds (0: never).
  TraceRecorder(Trace& trace, double snapshot_interval, double dt);
  /// Appends the world's current state.
  void operator()(const World& world);

 private:
  Trace& trace_;
  long snapshot_every_;
  long calls_ = 0;
};

}  // namespace plumetrace
